#!/usr/bin/env bash
# Digest of every vts command's output on the built-in cells, for checking
# that a change keeps the output byte for byte (issue 23).
#
#   scripts/output_digest.sh [BIN_DIR] > digest.txt      # BIN_DIR default: build/bin
#   diff digest-before.txt digest-after.txt
#
# One line per output: its sha256 and a label. Outputs are files (EXR, JSON
# Lines, CSV, PNG, STL/PLY/OBJ, NPZ, Markdown) and each command's stdout, and for
# bad input its stderr and exit code. The commands run in one fixed directory
# ($VTS_DIGEST_DIR, default /tmp/vts-output-digest, emptied first), so the
# absolute paths they print are the same for any build; that path is then
# written as <DIR>. What is not deterministic is masked, and only that:
#   - `vts scan`'s wall time and rate on its second stdout line
#     ("; 0.26 s (387 profiles/s)"), and its progress lines on stderr;
#   - `vts sim`'s wall time ("in 1.23 s" in the text, "wall_time_s" in --json);
#   - `vts dataset`'s wall time and rate ("written in 1.46 s (702 profiles/s)").
# Nothing else embeds a time, a version or a host: the EXR header holds the
# scanner and the scene only (docs/EXR_FORMAT.md), PNGs are stb's without
# metadata. `vts --version` and the --help texts are digested apart, at the
# end under "help:", since a new option changes them on purpose.
#
# Environment: VTS_DIGEST_KEEP=1 leaves the outputs in the directory;
# VTS_DIGEST_VIEWER=0 skips vts-view (it needs xvfb-run).
set -euo pipefail

bin=$(cd "${1:-build/bin}" && pwd)
src=$(cd "$(dirname "$0")/.." && pwd)
dir=${VTS_DIGEST_DIR:-/tmp/vts-output-digest}
vts="$bin/vts"
rm -rf "$dir"
mkdir -p "$dir"
cd "$dir"

mask() {
  sed -e "s|$dir|<DIR>|g" \
      -e 's|; [0-9.]* s ([0-9]* profiles/s)$|; <T> s (<R> profiles/s)|' \
      -e 's|simulated in [0-9.]* s|simulated in <T> s|' \
      -e 's|written in [0-9.]* s ([0-9]* profiles/s)$|written in <T> s (<R> profiles/s)|' \
      -e 's|"wall_time_s":[-0-9.e+]*|"wall_time_s":<T>|'
}
digest() {  # digest LABEL FILE...
  local label=$1 f
  shift
  for f in "$@"; do
    printf '%s  %s\n' "$(sha256sum <"$f" | cut -d' ' -f1)" "$label${f:+:$(basename "$f")}"
  done
}
# run LABEL ARGS...: runs vts, digests its masked stdout, and its stderr
# without progress lines; a non-zero exit code is part of the label's line.
run() {
  local label=$1 f
  shift
  local rc=0
  "$vts" "$@" >out.txt 2>err.txt || rc=$?
  printf '%s  %s\n' "$(mask <out.txt | sha256sum | cut -d' ' -f1)" "$label:stdout rc=$rc"
  if grep -Eqv '^(scan|dataset): ' err.txt; then
    printf '%s  %s\n' "$(grep -Ev '^(scan|dataset): ' err.txt | mask | sha256sum | cut -d' ' -f1)" "$label:stderr"
  fi
  rm -f out.txt err.txt
}

cells=$("$vts" cells | cut -d' ' -f1)
run cells cells
run sensors sensors
run sensors-plot sensors --plot sensors.png
digest sensors-plot sensors.png

mkdir -p scan track mesh plot
for c in $cells; do
  n=100
  [ "$c" = fillet-1m ] && n=30
  [ "$c" = saddle-1m ] && n=30
  run "scan/$c" scan --cell "$c" --profiles "$n" --out "scan/$c.exr"
  run "scan/$c-ref" scan --cell "$c" --reference --profiles 40 --seed 3 --out "scan/$c-ref.exr"
  run "scan/$c-ideal" scan --cell "$c" --ideal --reference --profiles 40 --out "scan/$c-ideal.exr"
  run "scan/$c-srcref" scan --cell "$c" --source reference --profiles 40 --seed 11 --out "scan/$c-srcref.exr"
  digest "scan/$c" "scan/$c.exr" "scan/$c-ref.exr" "scan/$c-ideal.exr" "scan/$c-srcref.exr"
  for f in "$c" "$c-ref" "$c-ideal" "$c-srcref"; do
    run "track/$f" track "scan/$f.exr" --out "track/$f.jsonl"
    digest "track/$f" "track/$f.jsonl"
  done
  run "track/$c-truth" track "scan/$c.exr" --truth --out "track/$c-truth.jsonl"
  digest "track/$c-truth" "track/$c-truth.jsonl"
  run "plot/$c" plot "scan/$c-ref.exr" --row 0 --row 20 --out "plot/$c.png"
  digest "plot/$c" "plot/$c.png"
  run "mesh/$c" mesh --cell "$c" --out "mesh/$c.ply"
  digest "mesh/$c" "mesh/$c.ply"
done

# More than one batch of 512, presets, materials, seeds, points, rates.
run scan/fillet-1100 scan --cell fillet --profiles 1100 --seed 5 --out scan/fillet-1100.exr
run scan/butt-1100-ref scan --cell butt --profiles 1100 --reference --out scan/butt-1100-ref.exr
run scan/lap-lps2048 scan --cell lap --sensor lps-2048-short --seed 7 --profiles 600 --out scan/lap-lps2048.exr
run scan/vgroove-lps1280 scan --cell vgroove --sensor lps-1280-mid --standoff 200 --profiles 50 --reference \
  --out scan/vgroove-lps1280.exr
run scan/lap-shiny scan --cell lap --material shiny-steel --seed 7 --out scan/lap-shiny.exr
run scan/corner-alu scan --cell corner --material aluminium --seed 2 --points 1024 --reference --out scan/corner-alu.exr
run scan/fillet-speed scan --cell fillet --standoff 80 --speed 40 --rate 100 --profiles 200 --out scan/fillet-speed.exr
run scan/plate-path scan --cell plate --source reference --start=10,-5,90 --direction 0,1,0 --step 0.25 \
  --out scan/plate-path.exr
for f in fillet-1100 butt-1100-ref lap-lps2048 vgroove-lps1280 lap-shiny corner-alu fillet-speed plate-path; do
  digest "scan/$f" "scan/$f.exr"
  run "track/$f" track "scan/$f.exr" --out "track/$f.jsonl"
  digest "track/$f" "track/$f.jsonl"
done
for y in "$src"/examples/*.yaml; do
  e=$(basename "$y" .yaml)
  run "scan/example-$e" scan --scene "$y" --reference --out "scan/example-$e.exr"
  digest "scan/example-$e" "scan/example-$e.exr"
  run "track/example-$e" track "scan/example-$e.exr" --out "track/example-$e.jsonl"
  digest "track/example-$e" "track/example-$e.jsonl"
  run "mesh/example-$e" mesh --scene "$y" --out "mesh/example-$e.obj"
  digest "mesh/example-$e" "mesh/example-$e.obj"
done
run mesh/fillet-stl mesh --cell fillet --out mesh/fillet.stl
digest mesh/fillet-stl mesh/fillet.stl

# vts export: every format, with and without the reference and the error model.
mkdir -p export
for f in fillet-ref fillet-ideal lap; do
  for x in csv ply npz; do
    run "export/$f-$x" export "scan/$f.exr" --out "export/$f.$x"
    digest "export/$f-$x" "export/$f.$x"
  done
done

# vts track: parameter file, options, joints, CSV input.
cat >params.yaml <<'EOF'
joint: vgroove
surface_tol_mm: 0.05
max_joint_width_mm: 25
square_edges: false
segmentation:
  roi_first: 2
  roi_last: -1
  ray_origin_yz: [0, 0]
  outliers: {enabled: true, max_cluster_points: 5, threshold_mm: 0.25, support_points: 3, support_tol_mm: 0.12}
  segments:
    split_threshold_mm: 0.35
    split_interval: 2
    min_segment_points: 7
    max_merge_gap_points: 9
    max_merge_angle_deg: 14
    max_merge_offset_mm: 0.25
    break_min_mm: 0.3
    break_ratio: 4
    fit_tol_mm: 0.03
fillet: {angle_deg: [40, 140], gap_mm: [0, 3.5], web: auto}
corner: {angle_deg: [60, 170], gap_mm: [0, 3]}
lap: {step_mm: [0.5, 30], gap_mm: [0, 3], angle_deg: [45, 135], max_plate_angle_deg: 15, upper_thickness_mm: 0}
butt: {gap_mm: [0, 5], mismatch_mm: [0, 3], max_plate_angle_deg: 15}
vgroove: {angle_deg: [20, 120], gap_mm: [0, 5], mismatch_mm: [0, 3], depth_mm: [0.5, 60], min_bevel_points: 4}
EOF
run track/params track scan/vgroove.exr --params params.yaml --out track/params.jsonl
run track/params-over track scan/vgroove.exr --params params.yaml --surface-tol 0.08 --split-threshold 0.5 \
  --split-interval 3 --min-segment 6 --merge-gap 8 --merge-angle 12 --outlier-threshold 0.35 --out track/params-over.jsonl
run track/fillet-ranges track scan/fillet.exr --joint fillet --angle 80,100 --gap 0,1 --out track/fillet-ranges.jsonl
run track/lap-thick track scan/lap.exr --joint lap --upper-thickness 3 --no-outliers --out track/lap-thick.jsonl
run track/butt-as-vgroove track scan/butt.exr --joint vgroove --out track/butt-as-vgroove.jsonl
run track/stdout track scan/corner-ideal.exr
for f in params params-over fillet-ranges lap-thick butt-as-vgroove; do digest "track/$f" "track/$f.jsonl"; done
{
  echo "profile,y,z,valid"
  for p in 0 1 2; do
    for i in $(seq 0 79); do
      y=$(awk -v i="$i" 'BEGIN { printf "%.6f", -20 + i * 0.5 }')
      z=$(awk -v i="$i" -v p="$p" 'BEGIN { y = -20 + i * 0.5; printf "%.6f", 100 - (y < 0 ? -y : y) + p * 0.01 }')
      echo "$p,$y,$z,1"
    done
  done
} >track/fillet.csv
run track/csv track track/fillet.csv --joint fillet --out track/csv.jsonl
digest track/csv track/csv.jsonl

# Bad input: the message and exit code (nothing written).
run err/scan-points scan --points 8
run err/scan-cell scan --cell tee
run err/scan-sensor scan --sensor foo
run err/scan-material scan --material foo
run err/scan-step-speed scan --step 1 --speed 2
run err/scan-seed scan --seed -1
run err/scan-start scan --start 1,2
run err/scan-standoff-scene scan --scene "$src/examples/vgroove.yaml" --standoff 50
run err/scan-source scan --source gpu
run err/scan-scene scan --scene "$src/tests/malformed/wrong-type.yaml"
run err/track-joint track scan/fillet.exr --joint tee
run err/track-params track scan/fillet.exr --params "$src/tests/malformed/params-wrong-type.yaml"
run err/track-split track scan/fillet.exr --split-interval 0
run err/track-angle-butt track scan/butt.exr --joint butt --angle 1,2
run err/track-gap track scan/fillet.exr --gap 3,1
run err/track-truth-ideal track scan/fillet-ideal.exr --truth
run err/track-ext track params.yaml
run err/track-csv track "$src/tests/malformed/bad-number.csv"
run err/static-profiles static --profiles 0
run err/sim-speed sim --speed 0
run err/sim-sensor sim --sensor foo
run err/mesh-ext mesh --cell fillet --out x.dxf
run err/plot-row plot scan/fillet.exr --row 500
run err/export-ext export scan/fillet.exr --out x.txt
run err/export-missing export missing.exr --out x.csv

# The paper's experiments.
run static static --out-dir static
digest static static/table3.csv static/table3.md static/static-*.png
run static-ref static --out-dir static-ref --source reference --profiles 5 --seed 2
digest static-ref static-ref/table3.csv static-ref/table3.md static-ref/static-*.png
run static-ideal static --out-dir static-ideal --ideal --profiles 3
digest static-ideal static-ideal/table3.csv static-ideal/static-A.png
run sim sim --json --out-dir sim
digest sim sim/timeseries.csv sim/profiles.exr sim/tracking_error.png
run sim-ref sim --out-dir sim-ref --source reference --seed 3 --speed 20
digest sim-ref sim-ref/timeseries.csv sim-ref/profiles.exr sim-ref/tracking_error.png
run sim-ideal sim --json --out-dir sim-ideal --ideal --sensor lps-1280-mid --rate 200 --offset 4 --rotation 2
digest sim-ideal sim-ideal/timeseries.csv sim-ideal/profiles.exr sim-ideal/tracking_error.png
run sim-replay sim --json --out-dir sim-replay --replay sim/profiles.exr
digest sim-replay sim-replay/timeseries.csv sim-replay/tracking_error.png

# A dataset (every file: EXRs, JSON Lines, records, manifest) and a bad spec.
run dataset dataset --spec "$src/examples/dataset.yaml" --out dataset
digest dataset dataset/*
cp "$src/tests/malformed/dataset-min-max.yaml" bad-spec.yaml
run err/dataset-spec dataset --spec bad-spec.yaml --out dataset-bad

# The viewer's recording (a scripted run waits for its scans, so the
# recording is deterministic; the screenshot is not digested: its panel
# shows frame times).
if [ "${VTS_DIGEST_VIEWER:-1}" = 1 ] && [ -x "$bin/vts-view" ] && command -v xvfb-run >/dev/null; then
  for args in "--cell vgroove" "--cell lap --source reference --sensor lps-1280-mid" "--cell static-E --ideal"; do
    name=$(echo "$args" | tr ' ' '_' | tr -d '-')
    # shellcheck disable=SC2086
    xvfb-run -a -s "-screen 0 1280x1024x24 -nolisten tcp" "$bin/vts-view" $args --frames 30 \
      --keys "p w*20 a*3 p" --record "view/$name.exr" >/dev/null 2>&1
    digest "view/$name" "view/$name.exr"
  done
  xvfb-run -a -s "-screen 0 1280x1024x24 -nolisten tcp" "$bin/vts-view" --sim --frames 40 --keys "p _*30 p" \
    --record view/sim.exr >/dev/null 2>&1
  digest view/sim view/sim.exr
fi

# Help texts and the version: expected to change with new options.
for c in "" scan track static sim mesh plot sensors dataset; do
  # shellcheck disable=SC2086
  "$vts" $c --help | sha256sum | sed "s|-\$|help:vts $c|"
done
"$vts" --version | sha256sum | sed 's|-$|help:version|'

cd /
[ "${VTS_DIGEST_KEEP:-0}" = 1 ] || rm -rf "$dir"
