// `frameless bench error`: its flags; the benchmark is bench::run_error (src/bench/bench_error.h).
#include <memory>

#include "bench/bench_error.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_error_registered = register_command(
    "bench", "error", "Static convergence: error of the displayed image vs time and samples",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::ErrorOptions>();
      app.add_option("scene", args->scene,
                     "Scene: built-in name, .json, .obj, .ply, .gltf or .glb (default: default)");
      add_shadow_flags(app, args->shadows);
      app.add_option("--out", args->out, "Output directory (error.json, error.csv, error.png)")
          ->required();
      app.add_option("--size", args->size, "Image size WxH (default 320x240)");
      app.add_option("--threads", args->threads, "Render threads (default: all hardware threads)");
      app.add_option("--seconds", args->seconds, "Seconds per mode (default 10)");
      app.add_option("--refresh", args->refresh, "Display refresh in Hz (default 30)");
      app.add_option("--alpha", args->alpha, "Frameless blend weight (default 0.5)");
      app.add_option("--ref-spp", args->ref_spp, "Reference samples per pixel (default 512)");
      app.add_option(
          "--cache", args->cache,
          "Reference cache directory (default $XDG_CACHE_HOME/frameless/references or OUT/cache)");
      app.add_flag("--quick", args->quick, "Smoke mode: 160x120, 3 s per mode, 64-spp reference");
      return [args]() { return bench::run_error(*args); };
    });

}  // namespace
}  // namespace frameless::cli
