#!/usr/bin/env bash
# The main job: builds frameless and runs it on the built-in showcase scene (soft shadows,
# image and solid textures, a cut-out, a glTF model). With a display it
# opens the interactive frameless viewer; without one it makes a short headless capture of the
# frameless display (OSMesa -> OpenEXR) into captures/ and says where to look.
# Extra arguments go to `frameless view` (or `frameless capture` when headless).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
tools/install-deps.sh
tools/build.sh build/release -DFRAMELESS_TESTS=OFF -- frameless >/dev/null
bin=build/release/tools/frameless

if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  echo "opening the frameless viewer on the showcase scene (H for help, Esc to quit)"
  "$bin" view showcase "$@" && exit 0
  echo "the viewer could not open a window; making a headless capture instead" >&2
fi
out=captures/showcase
"$bin" capture showcase --out "$out" --size 480x270 --duration 3 --refresh 30 --orbit 30 \
  --cut-at 2 --cut-orbit -35 --layers age,count "$@"
echo
echo "headless capture of the frameless display written to $out/:"
echo "  $out/contact_sheet.png   every frame at a glance (open it in any image viewer)"
echo "  $out/frame_*.exr         the frames (half RGB + age/count layers), e.g. for tev or exrdisplay"
echo "  $out/manifest.json       per-frame camera, timing, samples and coverage"
[ -f "$out/sequence.mp4" ] && echo "  $out/sequence.mp4        the sequence as a video"
echo "with a display, the same command opens the interactive viewer"
