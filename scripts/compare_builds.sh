#!/usr/bin/env bash
# Times two builds of vts against each other on a shared, noisy machine:
# runs each measurement alternately, OLD then NEW, ROUNDS times, and prints
# the median of each with the range (min..max) and the ratio new/old of the
# medians (docs/PERFORMANCE.md).
#
#   scripts/compare_builds.sh OLD_BIN_DIR NEW_BIN_DIR [ROUNDS]
#
# Environment: VTS_COMPARE_ONE_CORE=1 runs both builds on one core
# (`taskset -c 0`) with VTS_THREADS=1 (a build that has no thread limit then
# runs its threads on that core); VTS_COMPARE_QUICK=1 leaves out fillet-1m
# and vts sim.
#
# Measurements: `vts scan` end to end (profiles/s as it prints them) on
# static-B with the error model (bound by the EXR compression), with
# --ideal, with --reference (the raster checked against Embree), and with
# --source reference; on fillet-1m with --ideal; `vts sim` (wall time of the
# closed loop, one scan per profile); then vts-bench's source benchmarks
# (BM_Raster, BM_Reference on 1 and 2 benchmark threads, the Single and
# Batch ones), as items/s, each run once per round.
set -euo pipefail
old=$(cd "$1" && pwd)
new=$(cd "$2" && pwd)
rounds=${3:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

run=()
if [ "${VTS_COMPARE_ONE_CORE:-0}" = 1 ]; then
  export VTS_THREADS=1
  run=(taskset -c 0)
fi

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2)}'; }
range() { sort -g | awk 'NR == 1 {lo = $1} {hi = $1} END {printf "%g..%g", lo, hi}'; }
row() {  # row NAME OLD_VALUES NEW_VALUES (space-separated)
  local mo mn
  mo=$(tr ' ' '\n' <<<"$2" | grep . | median)
  mn=$(tr ' ' '\n' <<<"$3" | grep . | median)
  printf '%-52s old %10s (%s)   new %10s (%s)   new/old %.3f\n' "$1" "$mo" "$(tr ' ' '\n' <<<"$2" | grep . | range)" \
    "$mn" "$(tr ' ' '\n' <<<"$3" | grep . | range)" "$(awk -v a="$mn" -v b="$mo" 'BEGIN {print a / b}')"
}

# scan BIN ARGS...: profiles/s from the second line of stdout.
scan_rate() { "${run[@]}" "$1"/vts scan "${@:2}" --out s.exr | sed -n 2p | sed 's/.*s (\([0-9]*\) profiles\/s)$/\1/'; }
sim_time() { "${run[@]}" "$1"/vts sim --json --out-dir sim "${@:2}" | sed 's/.*"wall_time_s":\([0-9.e+-]*\).*/\1/'; }

declare -A results
measure() {  # measure NAME FUNCTION ARGS...
  local name=$1 fn=$2
  shift 2
  for _ in $(seq "$rounds"); do
    results["$name/old"]+="$($fn "$old" "$@") "
    results["$name/new"]+="$($fn "$new" "$@") "
  done
  row "$name" "${results[$name/old]}" "${results[$name/new]}"
}

echo "$(date -u '+%F %T') UTC; load $(cut -d' ' -f1-3 /proc/loadavg); ${run[*]:-all cores}; $rounds rounds"
echo "profiles/s: median (min..max), higher is better"
measure "scan static-B 20000, error model" scan_rate --cell static-B --profiles 20000
measure "scan static-B 20000 --ideal" scan_rate --cell static-B --profiles 20000 --ideal
measure "scan static-B 5000 --reference" scan_rate --cell static-B --profiles 5000 --reference
measure "scan static-B 20000 --source reference" scan_rate --cell static-B --profiles 20000 --source reference
if [ "${VTS_COMPARE_QUICK:-0}" != 1 ]; then
  measure "scan fillet-1m 20000 --ideal" scan_rate --cell fillet-1m --profiles 20000 --ideal
  echo "seconds: median (min..max), lower is better"
  measure "sim (raster, 670 profiles)" sim_time
fi

echo "vts-bench items/s: median (min..max) of the rounds' means"
filter='BM_(Raster|Reference|RasterSingle|ReferenceSingle|RasterBatch|ReferenceBatch)/static-B'
[ "${VTS_COMPARE_QUICK:-0}" != 1 ] &&
  filter='BM_(Raster|Reference|RasterSingle|ReferenceSingle|RasterBatch|ReferenceBatch)/(static-B|fillet-1m)'
for _ in $(seq "$rounds"); do
  for b in old new; do
    dir=$old
    [ $b = new ] && dir=$new
    "${run[@]}" "$dir"/vts-bench --benchmark_filter="$filter" --benchmark_min_time=0.5 --benchmark_format=csv 2>/dev/null |
      awk -F, -v b=$b 'NR > 1 && $1 !~ /^name/ {gsub(/"/, "", $1); print b "," $1 "," $7}' >>bench.csv
  done
done
for name in $(cut -d, -f2 bench.csv | sort -u); do
  row "$name" "$(grep ",$name," bench.csv | grep '^old' | cut -d, -f3 | tr '\n' ' ')" \
    "$(grep ",$name," bench.csv | grep '^new' | cut -d, -f3 | tr '\n' ' ')"
done
echo "$(date -u '+%F %T') UTC; load $(cut -d' ' -f1-3 /proc/loadavg)"
