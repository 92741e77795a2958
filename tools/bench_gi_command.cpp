// `frameless bench gi`: its flags; the benchmark is bench::run_gi (src/bench/bench_gi.h).
#include <memory>

#include "bench/bench_gi.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_gi_registered = register_command(
    "bench", "gi",
    "Light that bounces: path tracing's and igi's error vs wall time, beside Blender's Cycles when installed",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::GiOptions>();
      app.add_option("scene", args->scene, "Scene (default cornell; Cycles needs plain diffuse triangles)");
      add_shadow_flags(app, args->shadows);
      app.add_option("--out", args->out, "Output directory (gi.json, gi.png, reference PNGs)")->required();
      app.add_option("--size", args->size, "Image size WxH (default 128x128)");
      app.add_option("--threads", args->threads, "Render threads, for both renderers (default: all)");
      app.add_option("--ref-spp", args->ref_spp, "Converged references' samples per pixel (default 4096)");
      app.add_option("--spp", args->spp, "Cycles' sample counts compared (default 16 64 256)");
      app.add_option("--seconds", args->seconds, "frameless run length without Cycles (default 10)");
      app.add_flag("--no-cycles", args->no_cycles, "Skip Cycles even when blender is installed");
      app.add_option("--cache", args->cache,
                     "Reference cache directory (default $XDG_CACHE_HOME/frameless/references or OUT/cache)");
      app.add_flag("--quick", args->quick, "Smoke mode: 64x64, 512-spp references, Cycles at 4 and 16 spp");
      return [args]() { return bench::run_gi(*args); };
    });

}  // namespace
}  // namespace frameless::cli
