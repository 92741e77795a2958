// `frameless bench latency`: its flags; the benchmark is bench::run_latency
// (src/bench/bench_latency.h).
#include <memory>

#include "bench/bench_latency.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_latency_registered = register_command(
    "bench", "latency", "Camera change -> 50/95/100% of pixels showing it, against the ideal",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::LatencyOptions>();
      app.add_option("scene", args->scene,
                     "Scene: built-in name, .json, .obj, .ply, .gltf or .glb (default: default)");
      add_shadow_flags(app, args->shadows);
      app.add_option("--out", args->out,
                     "Output directory (latency.json, latency.csv, latency.png)")
          ->required();
      app.add_option("--size", args->size, "Image size WxH (default 320x240)");
      app.add_option("--threads", args->threads, "Render threads (default: all hardware threads)");
      app.add_option("--update-percents", args->percents,
                     "Update percentages (default 0.1,1,10,50)")
          ->delimiter(',');
      app.add_option("--repeats", args->repeats,
                     "Repeats per setting; medians reported (default 3)");
      app.add_option("--refresh", args->refresh, "Display refresh in Hz (default 240)");
      app.add_flag("--quick", args->quick, "Smoke mode: 160x120, update 1% and 10%, one repeat");
      return [args]() { return bench::run_latency(*args); };
    });

}  // namespace
}  // namespace frameless::cli
