// `frameless bench accel`: its flags; the benchmark is bench::run_accel (src/bench/bench_accel.h).
#include <memory>

#include "bench/bench_accel.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_accel_registered = register_command(
    "bench", "accel",
    "BVH against the hybrid grid per scene: build time, memory, Mrays/s, and what auto chooses",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::AccelOptions>();
      app.add_option("scenes", args->scenes,
                     "Scenes (default: default bunny teapot spheres:100000 room)");
      app.add_option("--size", args->size, "Camera rays WxH (default 320x240)");
      app.add_option("--repeats", args->repeats, "Timed repetitions; the median is reported (default 3)");
      app.add_flag("--json", args->json, "Print JSON instead of the table");
      app.add_option("--out", args->out, "Also write DIR/accel.json");
      return [args]() { return bench::run_accel(*args); };
    });

}  // namespace
}  // namespace frameless::cli
