// `frameless bench scaling`: its flags; the benchmark is bench::run_scaling
// (src/bench/bench_scaling.h).
#include <memory>

#include "bench/bench_scaling.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_scaling_registered = register_command(
    "bench", "scaling",
    "Samples/s and Mrays/s vs threads, oversubscribed too; efficiency vs linear",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::ScalingOptions>();
      app.add_option("scene", args->scene,
                     "Scene: built-in name, .json, .obj, .ply, .gltf or .glb (default: default)");
      add_shadow_flags(app, args->shadows);
      app.add_option("--out", args->out,
                     "Output directory (scaling.json, scaling.csv, scaling.png)")
          ->required();
      app.add_option("--size", args->size, "Image size WxH (default 320x240)");
      app.add_option("--threads", args->threads,
                     "Thread counts (default 1..cores, 2x and 4x cores)")
          ->delimiter(',');
      app.add_option("--seconds", args->seconds, "Seconds per measurement (default 2)");
      app.add_flag("--quick", args->quick, "Smoke mode: 160x120, 0.5 s per point");
      return [args]() { return bench::run_scaling(*args); };
    });

}  // namespace
}  // namespace frameless::cli
