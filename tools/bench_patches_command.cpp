// `frameless bench patches`: its flags; the benchmark is bench::run_patches
// (src/bench/bench_patches.h).
#include <memory>

#include "bench/bench_patches.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_patches_registered = register_command(
    "bench", "patches",
    "Spline patches ray traced directly against the same patches tessellated, and Broyden's "
    "iteration counts",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::PatchesOptions>();
      add_shadow_flags(app, args->shadows);
      app.add_option("scene", args->scene, "Scene with spline patches (default: teapot)");
      app.add_option("--size", args->size, "Image size WxH (default 320x240)");
      app.add_option("--spp", args->spp, "Samples per pixel of each timed image (default 2)");
      app.add_option("--repeats", args->repeats, "Timed repetitions; the median is reported (default 3)");
      app.add_option("--levels", args->levels, "Quads per patch side to tessellate with (default 4 8 16 32 64)");
      app.add_flag("--json", args->json, "Print JSON instead of the table");
      app.add_option("--out", args->out, "Also write DIR/patches.json");
      return [args]() { return bench::run_patches(*args); };
    });

}  // namespace
}  // namespace frameless::cli
