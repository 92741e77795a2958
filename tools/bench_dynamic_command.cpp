// `frameless bench dynamic`: its flags; the benchmark is bench::run_dynamic
// (src/bench/bench_dynamic.h).
#include <memory>

#include "bench/bench_dynamic.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_dynamic_registered = register_command(
    "bench", "dynamic",
    "Samples/s against the number of moving objects (tested per ray, outside the BVH)",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::DynamicOptions>();
      app.add_option("scene", args->scene, "Scene the balls bounce in (default: default)");
      app.add_option("--counts", args->counts, "Numbers of moving objects (default 0 1 2 4 ... 128)");
      app.add_option("--size", args->size, "Image size WxH (default 256x144)");
      app.add_option("--spp", args->spp, "Samples per pixel of each timed image (default 2)");
      app.add_option("--repeats", args->repeats, "Timed repetitions; the median is reported (default 3)");
      app.add_flag("--json", args->json, "Print JSON instead of the table");
      app.add_option("--out", args->out, "Also write DIR/dynamic.json");
      return [args]() { return bench::run_dynamic(*args); };
    });

}  // namespace
}  // namespace frameless::cli
