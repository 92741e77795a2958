// `frameless bench all`: its flags; the benchmark is bench::run_all (src/bench/bench_all.h).
#include <memory>

#include "bench/bench_all.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_all_registered = register_command(
    "bench", "all", "Runs error, motion, latency, scaling and scale into one directory",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::AllOptions>();
      app.add_option("--out", args->out,
                     "Output directory (NAME.json/csv/png per benchmark, summary.json)")
          ->required();
      app.add_option("--scene", args->scene,
                     "Scene for error, motion, latency and scaling (default: default)");
      app.add_option(
          "--max-n", args->max_n,
          "Largest spheres:N for the scale benchmark (default 1e6; 3.5e7 for the full run)");
      app.add_option(
          "--cache", args->cache,
          "Reference cache directory (default $XDG_CACHE_HOME/frameless/references or OUT/cache)");
      app.add_flag("--quick", args->quick, "Smoke mode for every benchmark");
      return [args]() { return bench::run_all(*args); };
    });

}  // namespace
}  // namespace frameless::cli
