// `frameless bench engine`: its flags; the benchmark is bench::run_engine
// (src/bench/bench_engine.h).
#include <memory>

#include "bench/bench_engine.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_engine_registered = register_command(
    "bench", "engine", "Frameless vs conventional samples/s, display CPU, camera-change latency",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::EngineBenchOptions>();
      app.add_option("scene", args->scene, "Scene: built-in name, .json, .obj, .ply, .gltf or .glb (default: default)");
      add_shadow_flags(app, args->shadows);
      app.add_option("--size", args->size, "Image size WxH for throughput and latency (default 640x360)");
      app.add_option("--threads", args->threads, "Render threads (default: all hardware threads)");
      app.add_option("--seconds", args->seconds, "Seconds per throughput measurement (default 2)");
      app.add_option("--repeats", args->repeats,
                     "Repetitions of each measurement (throughput pairs interleaved); medians "
                     "are reported (default 3)");
      app.add_option("--budget", args->budget,
                     "Reprojection budget measured beside the unlimited default, a fraction of "
                     "one core (default 0.15)");
      app.add_option("--moving-sizes", args->moving_sizes,
                     "Also measure the display thread during the move with reprojection at these "
                     "sizes WxH, alone and with a consumer taking every image as the viewer does "
                     "(default: 1280x720 only)");
      app.add_option("--render-nice", args->render_nice,
                     "Render threads' nice value above the display's, 0..19 (default " +
                         std::to_string(kDefaultRenderNice) + ")");
      app.add_flag("--json", args->json, "Print JSON");
      return [args]() { return bench::run_engine(*args); };
    });

}  // namespace
}  // namespace frameless::cli
