#!/bin/sh
# vts-view's headless check (README "Viewer"): runs the viewer under Xvfb
# twice for the same number of frames, without keys and with keys that drive
# the torch forward, then once recording with P, and asserts on the results
# with viewer_image_check.
#
# usage: screenshot_test.sh VTS_VIEW VIEWER_IMAGE_CHECK OUT_DIR
set -eu
view=$1
check=$2
out=$3
mkdir -p "$out"
rm -f "$out/a.png" "$out/b.png" "$out/recording.exr"

if command -v xvfb-run >/dev/null 2>&1; then
  # A 24-bit screen: GLX on the default 8-bit one has no 3.3 core visual.
  run() { xvfb-run -a -s "-screen 0 1280x1024x24 -nolisten tcp" "$view" "$@"; }
elif [ -n "${DISPLAY:-}" ]; then
  run() { "$view" "$@"; }
else
  echo "screenshot_test: needs xvfb-run (Debian: apt-get install xvfb; scripts/setup.sh installs it) or a \$DISPLAY" >&2
  exit 1
fi

# "... 3D view x < W; TCP at pixel X Y; nozzle at pixel X Y" -> "W X Y X Y"
numbers() {
  sed -n 's/.*3D view x < \([0-9]*\); TCP at pixel \([-0-9]*\) \([-0-9]*\); nozzle at pixel \([-0-9]*\) \([-0-9]*\).*/\1 \2 \3 \4 \5/p'
}

echo "== A: 43 frames, no keys"
line_a=$(run --screenshot "$out/a.png" --frames 43)
echo "$line_a"
echo "== B: the same 43 frames, the torch driven forward for 40 (w*40)"
line_b=$(run --screenshot "$out/b.png" --keys "w*40")
echo "$line_b"
set -- $(echo "$line_a" | numbers) $(echo "$line_b" | numbers)
if [ $# -ne 10 ]; then
  echo "screenshot_test: vts-view did not report its screenshot as expected" >&2
  exit 1
fi
# view width, then TCP and nozzle pixels of A and of B
"$check" shots "$out/a.png" "$out/b.png" "$1" "$2" "$3" "$4" "$5" "$7" "$8" "$9" "${10}"

echo "== C: record 20 frames (2/3 s at 20 Hz) with P ... P"
run --frames 25 --keys "p w*20 p" --record "$out/recording.exr"
"$check" exr "$out/recording.exr" 12 512
