#!/usr/bin/env bash
# The main job: builds frameless and runs it on the built-in default scene. With a display it
# opens the interactive viewer; without one it renders headless into captures/ and says where.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
tools/install-deps.sh
tools/build.sh build/release -DFRAMELESS_TESTS=OFF -- frameless >/dev/null
bin=build/release/tools/frameless
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ] && "$bin" view --help >/dev/null 2>&1; then
  exec "$bin" view default "$@"
fi
mkdir -p captures
if "$bin" capture --help >/dev/null 2>&1; then
  "$bin" capture default --out captures/default "$@"
else
  "$bin" render default --size 640x480 --out captures/default.exr --png captures/default.png "$@"
  echo "look at it: captures/default.png (8-bit sRGB) or captures/default.exr (HDR, with Z and N)"
fi
