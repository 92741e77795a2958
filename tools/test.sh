#!/usr/bin/env bash
# Builds and runs every test, each suite once, in the build whose checks fit it: ASan+UBSan for the
# core, readers and display (memory, parsers, raw-pointer loops), ThreadSanitizer for the engine,
# the render -> display -> consumer exchange, the API, the viewer's threads and whole mpirun
# cluster jobs, and Release for the command line, the viewer (scripted times), the cluster, the
# Python module and the installed API; then the scene/mesh/wire parser fuzzer for a bounded time.
# Usage: tools/test.sh [--quick | --cluster-tsan]   (--quick: every suite in Release only;
#        --cluster-tsan: only whole mpirun jobs of a ThreadSanitizer build)
# Env: FRAMELESS_FUZZ_SECONDS (default 60), FRAMELESS_LONG_TESTS=1 for long stress runs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
tools/install-deps.sh --test
jobs=$(nproc 2>/dev/null || echo 2)
quick=0; [ "${1:-}" = "--quick" ] && quick=1
cluster_tsan=0; [ "${1:-}" = "--cluster-tsan" ] && cluster_tsan=1

start=$(date +%s)
section() { printf '\n=== %s (at %ds) ===\n' "$*" $(($(date +%s) - start)); }
# CI's 2 cores spend most of its time compiling: clang (about half g++'s time here) in unity
# builds (a library's files compiled in batches: 6.5 instead of 10.7 minutes for the Release build).
clang=(-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DCMAKE_UNITY_BUILD=ON)
# The ThreadSanitizer build of the engine, exchange and API suites, the viewer's tests and the
# command line (cluster jobs); the command line and benchmarks themselves unoptimized (compile time).
tsan_build=(build/tsan "${clang[@]}" -DFRAMELESS_SANITIZE=thread -DCMAKE_BUILD_TYPE=Sanitize
            -DCMAKE_CXX_FLAGS_SANITIZE='-O1 -g1' -DFRAMELESS_UNOPTIMIZED_DRIVERS=ON
            "-DFRAMELESS_TEST_SUITES=engine;exchange;api;viewer")

cluster_tsan_jobs() {
  # Whole cluster jobs (master + 2 clients) with the frameless binary under ThreadSanitizer:
  # wall-clock and deterministic captures and bench cluster. Open MPI and Mesa are not
  # instrumented; tests/tsan_mpi.supp silences reports from inside them only.
  tools/build.sh "${tsan_build[@]}" -- frameless
  local bin=build/tsan/tools/frameless out=build/tsan/cluster-jobs
  local tsan="halt_on_error=1 second_deadlock_stack=1 suppressions=$root/tests/tsan_mpi.supp"
  local mpi=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout 600
             mpirun --oversubscribe --mca btl self,vader -np 3 -x TSAN_OPTIONS="$tsan")
  rm -rf "$out"
  "${mpi[@]}" "$bin" capture default --size 64x48 --threads 1 --refresh 20 --duration 2 --no-mp4 \
    --orbit 40 --out "$out/wall"
  "${mpi[@]}" "$bin" capture default --deterministic --size 64x48 --threads 2 --refresh 20 \
    --duration 1 --no-mp4 --orbit 40 --out "$out/deterministic"
  "${mpi[@]}" "$bin" bench cluster --one --size 160x90 --seconds 1 --threads 1 --cluster-wire rgbe >/dev/null
  # Conventional frames: pieces on demand (two render threads per client take them from the
  # communication thread's queue), and a deterministic run with states handed between clients.
  "${mpi[@]}" "$bin" capture default --mode conventional --size 64x48 --threads 2 --refresh 20 \
    --duration 2 --no-mp4 --orbit 40 --out "$out/conventional"
  "${mpi[@]}" "$bin" capture default --mode conventional --deterministic --size 48x36 --threads 1 \
    --refresh 20 --duration 1 --no-mp4 --samples-per-tick 700 --out "$out/conventional-det"
}
if [ $cluster_tsan = 1 ]; then
  section "ThreadSanitizer: whole cluster jobs under mpirun"
  cluster_tsan_jobs
  section "cluster jobs clean under ThreadSanitizer"
  exit 0
fi

if [ $quick = 1 ]; then
  section "Release build and every suite"
  tools/build.sh build/test-release "${clang[@]}" -DFRAMELESS_TESTS=ON -DFRAMELESS_TEST_SUITES=
  (cd build/test-release && ctest -j"$jobs" --output-on-failure)
  exit 0
fi

section "Release build and tests (command line, viewer, cluster, Python module, installed API, docs)"
# run.sh and the benchmarks use g++ in build/release; this is clang's.
tools/build.sh build/test-release "${clang[@]}" -DFRAMELESS_TESTS=ON "-DFRAMELESS_TEST_SUITES=cli;viewer;cluster"
(cd build/test-release && ctest -j"$jobs" --output-on-failure -L 'cli|viewer|cluster|python|install|docs')

section "ASan+UBSan build and tests (core, readers, display)"
# The same build links the parser fuzzer.
tools/build.sh build/asan "${clang[@]}" \
  -DFRAMELESS_SANITIZE=address,undefined -DFRAMELESS_FUZZ=ON -DCMAKE_BUILD_TYPE=Sanitize \
  -DCMAKE_CXX_FLAGS_SANITIZE='-O1 -g1' "-DFRAMELESS_TEST_SUITES=core;readers;display" \
  -- core_tests reader_tests display_tests scene_fuzzer
(cd build/asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0" \
  ctest -j"$jobs" --output-on-failure -L 'core|readers|display')

section "ThreadSanitizer build and tests (engine, render -> display -> consumer exchange, the API, the viewer's threads)"
tools/build.sh "${tsan_build[@]}" -- engine_tests exchange_tests api_tests viewer_tests frameless
# The API's captures draw through OSMesa, whose rasteriser threads are not instrumented: reports
# from inside it (and Open MPI, and the viewer's Mesa GLX driver) are suppressed; our code's
# accesses still report. The viewer's tests run one at a time (their screenshots are timed).
(cd build/tsan && export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$root/tests/tsan_mpi.supp" &&
  ctest -j"$jobs" --output-on-failure -L 'engine|exchange|api' &&
  ctest -j1 --output-on-failure -R 'Panels\.(ShowOver|SceneSettings|ErrorPlot)')

section "ThreadSanitizer: whole cluster jobs under mpirun (master's communication thread, clients)"
cluster_tsan_jobs

section "libFuzzer: scene and mesh parsers (${FRAMELESS_FUZZ_SECONDS:-60} s; built in the ASan stage)"
mkdir -p build/asan/fuzz-corpus
build/asan/tests/fuzz/scene_fuzzer -max_total_time="${FRAMELESS_FUZZ_SECONDS:-60}" \
  -rss_limit_mb=2048 -max_len=65536 build/asan/fuzz-corpus tests/fuzz/corpus 2>build/asan/fuzz.log ||
  { tail -50 build/asan/fuzz.log; exit 1; }
echo "fuzzer: $(grep -c . build/asan/fuzz.log) log lines, no crash"
section "all test stages passed"
