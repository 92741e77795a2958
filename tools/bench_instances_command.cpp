// `frameless bench instances`: its flags; the benchmark is bench::run_instances
// (src/bench/bench_instances.h).
#include <memory>

#include "bench/bench_instances.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_instances_registered = register_command(
    "bench", "instances",
    "cost of moving instances: copy, refit or rebuild of the top level, and the rays' speed after",
    [](CLI::App& app) {
      auto a = std::make_shared<bench::InstancesOptions>();
      app.add_option("scene", a->scene, "a scene with instances (built-in name or scene file)")
          ->capture_default_str();
      app.add_option("--reps", a->reps, "repetitions; the best is reported")->capture_default_str()->check(CLI::Range(1, 1000));
      app.add_option("--size", a->size, "camera rays per side for the ray-speed comparison")
          ->capture_default_str()->check(CLI::Range(8, 4096));
      app.add_flag("--json", a->json, "print one JSON object instead of a table");
      return [a] { return bench::run_instances(*a); };
    });

}  // namespace
}  // namespace frameless::cli
