#!/usr/bin/env bash
# Draws docs/architecture.svg, the libraries and their links, from the build itself: CMake's
# --graphviz output of a configure (nothing is compiled) rendered by Graphviz's dot, so the
# picture cannot drift from the code. Usage: tools/architecture.sh [OUT.svg | --check]
# --check: draws it afresh and fails when docs/architecture.svg differs (a test runs this).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
check=0
out=${1:-$root/docs/architecture.svg}
if [ "$out" = "--check" ]; then check=1; out=$(mktemp --suffix=.svg); fi
tools_dir=$root/tools
"$tools_dir/install-deps.sh" --docs
dir=$(mktemp -d)
trap 'rm -rf "$dir"; [ $check = 0 ] || rm -f "$out"' EXIT
# Our targets only: third-party libraries and the test suites would hide the layers.
cat >"$dir/CMakeGraphVizOptions.cmake" <<'OPTS'
set(GRAPHVIZ_GRAPH_NAME "frameless")
set(GRAPHVIZ_EXTERNAL_LIBS FALSE)
set(GRAPHVIZ_GENERATE_PER_TARGET FALSE)
set(GRAPHVIZ_GENERATE_DEPENDERS FALSE)
OPTS
cmake -S "$root" -B "$dir" -DFRAMELESS_TESTS=OFF --graphviz="$dir/frameless.dot" >"$dir/configure.log" 2>&1 ||
  { cat "$dir/configure.log" >&2; exit 1; }
# Top to bottom (arrows point down, to what a library links), one colour per floor.
python3 - "$dir/frameless.dot" "$dir/styled.dot" <<'PY'
import re, sys
src, dst = sys.argv[1], sys.argv[2]
text = open(src).read()
# One colour per floor: tools and bench, display and cluster, engine, core (docs/architecture.md).
floors = {"frameless": "#f4d6a0", "frameless_bench": "#f4d6a0", "frameless_cluster": "#e8c3e0",
          "frameless_display": "#e8c3e0", "frameless_display_thread": "#e8c3e0",
          "frameless_engine": "#c8d8f0", "frameless_core": "#eeeeee"}
def style(m):
    line = m.group(0)
    label = re.search(r'label = "([^"]+)"', line).group(1)
    colour = floors.get(label, "#cfe8cf")  # the core's seven libraries
    return line.replace('];', ', style = "filled", fillcolor = "%s" ];' % colour)
# CMake's legend explains its shapes; ours are all libraries and the executable.
text = re.sub(r'subgraph clusterLegend \{.*?\n\}\n', '', text, flags=re.S)
text = re.sub(r'^\s*"node\d+" \[[^\n]*\];$', style, text, flags=re.M)
text = text.replace('node [\n', 'rankdir = "TB";\nnodesep = 0.25;\nranksep = 0.35;\nnode [\n', 1)
open(dst, 'w').write(text)
PY
# tred keeps each library's direct links only: a link implied by a path through others is drawn
# once, as that path (an upward link would still show, as a cycle).
tred "$dir/styled.dot" >"$dir/reduced.dot"
dot -Tsvg "$dir/reduced.dot" -o "$out"
if [ $check = 1 ]; then
  cmp -s "$out" "$root/docs/architecture.svg" ||
    { echo "docs/architecture.svg is out of date with the CMake targets: run tools/architecture.sh" >&2; exit 1; }
  echo "docs/architecture.svg matches the build ($(grep -c '<g id="node' "$out") libraries)"
else
  echo "wrote $out ($(grep -c '<g id="node' "$out") libraries)"
fi
