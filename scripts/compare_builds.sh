#!/usr/bin/env bash
# Times two builds of vts against each other on a shared, noisy machine:
# runs each measurement alternately, OLD then NEW, ROUNDS times, and prints
# the median of each (docs/PERFORMANCE.md).
#
#   scripts/compare_builds.sh OLD_BIN_DIR NEW_BIN_DIR [ROUNDS]
#
# Measurements: `vts scan` end to end (profiles/s as it prints them) on
# static-B with the error model (bound by the EXR compression), with --ideal,
# and with --reference; on fillet-1m; `vts sim` (wall time of the closed
# loop, one scan per profile); then vts-bench's source benchmarks (BM_Raster,
# BM_Reference on 1 and 2 benchmark threads, the Single and Batch ones), as
# items/s, each run once per round.
set -euo pipefail
old=$(cd "$1" && pwd)
new=$(cd "$2" && pwd)
rounds=${3:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2)}'; }

# scan LABEL ARGS...: profiles/s from the second line of stdout.
scan_rate() { "$1"/vts scan "${@:2}" --out s.exr | sed -n 2p | sed 's/.*s (\([0-9]*\) profiles\/s)$/\1/'; }
sim_time() { "$1"/vts sim --json --out-dir sim "${@:2}" | sed 's/.*"wall_time_s":\([0-9.e+-]*\).*/\1/'; }

declare -A results
measure() {  # measure NAME FUNCTION ARGS...
  local name=$1 fn=$2
  shift 2
  for _ in $(seq "$rounds"); do
    results["$name/old"]+="$($fn "$old" "$@") "
    results["$name/new"]+="$($fn "$new" "$@") "
  done
  printf '%-40s old %10s   new %10s   (%s rounds)\n' "$name" \
    "$(tr ' ' '\n' <<<"${results[$name/old]}" | grep . | median)" \
    "$(tr ' ' '\n' <<<"${results[$name/new]}" | grep . | median)" "$rounds"
}

echo "profiles/s (median), higher is better"
measure "scan static-B 20000, error model" scan_rate --cell static-B --profiles 20000
measure "scan static-B 20000 --ideal" scan_rate --cell static-B --profiles 20000 --ideal
measure "scan static-B 5000 --reference" scan_rate --cell static-B --profiles 5000 --reference
measure "scan fillet-1m 20000 --ideal" scan_rate --cell fillet-1m --profiles 20000 --ideal
echo "seconds (median), lower is better"
measure "sim (raster, 670 profiles)" sim_time

echo "vts-bench items/s (median of the rounds' means)"
filter='BM_(Raster|Reference|RasterSingle|ReferenceSingle|RasterBatch|ReferenceBatch)/(static-B|fillet-1m)'
for _ in $(seq "$rounds"); do
  for b in old new; do
    dir=$old
    [ $b = new ] && dir=$new
    "$dir"/vts-bench --benchmark_filter="$filter" --benchmark_min_time=0.5 --benchmark_format=csv 2>/dev/null |
      awk -F, -v b=$b 'NR > 1 && $1 !~ /^name/ {gsub(/"/, "", $1); print b "," $1 "," $7}' >>bench.csv
  done
done
for name in $(cut -d, -f2 bench.csv | sort -u); do
  printf '%-60s old %10.0f   new %10.0f\n' "$name" \
    "$(grep ",$name," bench.csv | grep '^old' | cut -d, -f3 | median)" \
    "$(grep ",$name," bench.csv | grep '^new' | cut -d, -f3 | median)"
done
