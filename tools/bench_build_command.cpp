// `frameless bench build`: its flags; the benchmark is bench::run_build (src/bench/bench_build.h).
#include <memory>

#include "bench/bench_build.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_build_registered = register_command(
    "bench", "build",
    "BVH build time, serial and parallel, against Embree's with 1 and N threads", [](CLI::App& app) {
      auto a = std::make_shared<bench::BuildOptions>();
      app.add_option("scenes", a->scenes, "scenes (built-in names, scene files or models)")
          ->capture_default_str();
      app.add_option("--threads", a->threads,
                     "threads for the parallel builds (default: all cores)");
      app.add_option("--reps", a->reps, "repetitions; the best of them is reported")
          ->capture_default_str();
      app.add_flag("--json", a->json, "print one JSON array instead of tables");
      app.add_flag("--no-embree", a->no_embree, "skip Embree (when built with it)");
      app.add_flag("--shuffle", a->shuffle,
                   "put the primitives in a fixed random order first (default: as loaded, which "
                   "is the leaf order of the load's own build)");
      return [a] { return bench::run_build(*a); };
    });

}  // namespace
}  // namespace frameless::cli
