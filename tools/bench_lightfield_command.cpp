// `frameless bench lightfield`: its flags; the benchmark is bench::run_lightfield
// (src/bench/bench_lightfield.h).
#include <memory>

#include "bench/bench_lightfield.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_lightfield_registered = register_command(
    "bench", "lightfield",
    "A light slab against its model: bake time, memory, RMSE from novel viewpoints and the cost of a frame",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::LightfieldBenchOptions>();
      app.add_option("--model", args->model, "Scene or model to bake")->capture_default_str();
      app.add_option("--resolutions", args->resolutions, "Slab resolutions UVxUV:STxST (default 8x8:64x64 16x16:128x128 16x16:256x256)");
      app.add_option("--size", args->size, "Image size WxH of the comparisons")->capture_default_str();
      app.add_option("--spp", args->spp, "Samples per texel (bake) and per pixel (renders)")->capture_default_str();
      app.add_option("--repeats", args->repeats, "Timed repetitions; the median is reported")->capture_default_str();
      app.add_option("--threads", args->threads, "Baking threads (default: all cores); renders are timed on 1");
      app.add_flag("--json", args->json, "Print JSON instead of the table");
      app.add_option("--out", args->out, "Also write DIR/lightfield.json");
      return [args]() { return bench::run_lightfield(*args); };
    });

}  // namespace
}  // namespace frameless::cli
