#!/usr/bin/env bash
# Checks that a change altered no image: renders and deterministic captures of every built-in
# scene (and the shadow, accel, motion and conventional variants) made by two builds of
# `frameless`, compared byte for byte except the render-time attribute of render's EXRs.
# Usage: tools/compare_builds.sh OLD_FRAMELESS NEW_FRAMELESS [OUT_DIR]   (about 15 s on 2 cores)
# Exits 1 when any output differs or fails. Make the old binary from a worktree of the commit
# before: git worktree add /tmp/old COMMIT && tools/build.sh /tmp/old-build -- frameless (in it).
set -uo pipefail
if [ $# -lt 2 ] || [ "$1" = "-h" ] || [ "$1" = "--help" ]; then
  sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; [ $# -ge 2 ] || exit 2; exit 0
fi
old=$1 new=$2 out=${3:-build/compare-builds}
for b in "$old" "$new"; do
  [ -x "$b" ] || { echo "compare_builds.sh: $b: not an executable" >&2; exit 2; }
done
rm -rf "$out"; mkdir -p "$out/old" "$out/new"
same=0 diff=0 failed=0
# Both builds make one output: run FILE_OR_DIR frameless-arguments...
run() {
  local name=$1; shift
  for v in old new; do
    local bin=$old; [ $v = new ] && bin=$new
    "$bin" "$@" "$out/$v/$name" >"$out/$v/$name.log" 2>&1 ||
      { echo "FAIL  $v: frameless $* (see $out/$v/$name.log)"; failed=$((failed + 1)); }
  done
}
# Pixel data equal: everything but the value of frameless:render_seconds.
equal() {
  python3 - "$1" "$2" <<'PY'
import struct, sys
def norm(path):
    b = bytearray(open(path, 'rb').read())
    key = b'frameless:render_seconds\0'
    i = b.find(key)
    if i >= 0:
        j = b.index(b'\0', i + len(key)) + 1  # past the type name
        n = struct.unpack('<i', b[j:j + 4])[0]
        b[j + 4:j + 4 + n] = bytes(n)
    return bytes(b)
sys.exit(0 if norm(sys.argv[1]) == norm(sys.argv[2]) else 1)
PY
}
compare() {
  if [ ! -f "$out/old/$1" ] || [ ! -f "$out/new/$1" ]; then echo "MISSING $1"; diff=$((diff + 1))
  elif equal "$out/old/$1" "$out/new/$1"; then same=$((same + 1))
  else echo "DIFF  $1"; diff=$((diff + 1)); fi
}
render=(render --size 160x120 --threads 2)
for s in default showcase balls teapot room bunny sunflowers:300 spheres:20000; do
  n=${s//:/_}.exr
  run "$n" "${render[@]}" "$s" --spp 4 --out; compare "$n"
done
run default_area.exr "${render[@]}" default --spp 4 --shadows area --shadow-samples 8 --transparent-shadows --out
run room_grid.exr "${render[@]}" room --spp 2 --accel grid --out
run showcase_auto.exr "${render[@]}" showcase --spp 2 --accel auto --shadows hard --out
run balls_moved.exr "${render[@]}" balls --spp 2 --time 1.5 --out
for n in default_area room_grid showcase_auto balls_moved; do compare $n.exr; done
capture=(capture --deterministic --size 96x72 --threads 2 --refresh 20 --duration 1 --no-mp4)
run cap_conventional "${capture[@]}" default --mode conventional --out
for s in default balls teapot; do run "cap_$s" "${capture[@]}" "$s" --orbit 30 --out; done
for d in cap_conventional cap_default cap_balls cap_teapot; do
  for f in "$out/old/$d"/frame_*.exr; do [ -f "$f" ] && compare "$d/$(basename "$f")"; done
done
echo "compared: $same identical, $diff different, $failed failed runs"
[ $diff = 0 ] && [ $failed = 0 ]
