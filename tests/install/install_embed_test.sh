#!/usr/bin/env bash
# The installed API works for an application: `cmake --install` of this build into a fresh
# prefix, examples/embed configured with find_package(frameless) against that prefix alone and
# built, then run under Xvfb for 30 frames (half a second), orbiting; it must report samples, pixel
# updates its display showed, and a window that is not black (read back).
# Usage: install_embed_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
for f in include/frameless/api.h lib/cmake/frameless/frameless-config.cmake lib/libframeless.so; do
  [ -e "$tmp/prefix/$f" ] || { echo "not installed: $f" >&2; exit 1; }
done
cmake -S "$src/examples/embed" -B "$tmp/embed" -G Ninja -DCMAKE_PREFIX_PATH="$tmp/prefix" >"$tmp/configure.log" 2>&1 ||
  { cat "$tmp/configure.log" >&2; exit 1; }
cmake --build "$tmp/embed" >"$tmp/build.log" 2>&1 || { cat "$tmp/build.log" >&2; exit 1; }
out=$(xvfb-run -a -s '-screen 0 640x480x24' "$tmp/embed/embed" default --frames 30 --orbit)
echo "$out"
echo "$out" | grep -Eq 'embed: default, .* [1-9][0-9]* samples .* [1-9][0-9]* pixel updates shown, window mean 0\.[0-9]*[1-9]'
