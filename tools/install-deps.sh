#!/usr/bin/env bash
# Installs the Debian 12 packages frameless needs, only when some are missing (idempotent, quiet
# when everything is present). Usage: tools/install-deps.sh [--test] [--bench] [--docs] [--fixtures]
set -euo pipefail

build_pkgs=(build-essential cmake ninja-build pkg-config git libglm-dev libopenexr-dev nlohmann-json3-dev
  libtinyobjloader-dev libcli11-dev libpng-dev zlib1g-dev libglfw3-dev libosmesa6-dev libgl-dev
  libgtest-dev glmark2-data libjpeg62-turbo-dev libtinygltf-dev assimp-testmodels povray-examples
  libopenmpi-dev openmpi-bin libblosc-dev pybind11-dev libimgui-dev python3-dev python3-numpy)
test_pkgs=(xvfb xauth clang libclang-rt-14-dev graphviz python3 python3-pytest)
# valgrind: tools/ray_instructions.py counts instructions per ray with callgrind
bench_pkgs=(libembree-dev gnuplot blender libopenvdb-tools python3-openvdb python3-numpy valgrind)
# tests/data/volumes/make_vdb_fixtures.cpp (by hand only: it rewrites the OpenVDB test fixtures
# with OpenVDB itself; frameless's own reader links none of these)
fixtures_pkgs=(libopenvdb-dev libboost-dev libboost-iostreams-dev)
# tools/architecture.sh: dot draws docs/architecture.svg, python3 styles it; matplotlib: docs/python.md's plot
docs_pkgs=(graphviz python3 python3-matplotlib)

want=("${build_pkgs[@]}")
for arg in "$@"; do
  case "$arg" in
    --test) want+=("${test_pkgs[@]}") ;;
    --bench) want+=("${bench_pkgs[@]}") ;;
    --docs) want+=("${docs_pkgs[@]}") ;;
    --fixtures) want+=("${fixtures_pkgs[@]}") ;;
    *) echo "install-deps.sh: unknown option '$arg' (use --test, --bench, --docs, --fixtures)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps.sh: missing packages (${missing[*]}); run as root or install them" >&2
  exit 1
fi
echo "installing: ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq >/dev/null
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
