// `frameless bench ablation`: its flags; the benchmark is bench::run_ablation
// (src/bench/bench_ablation.h).
#include <memory>

#include "bench/bench_ablation.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_ablation_registered = register_command(
    "bench", "ablation",
    "Each skip of the per-sample path (and variance tracking, adaptive sampling) off vs on: "
    "time saved and image unchanged",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::AblationOptions>();
      app.add_option("scene", args->scene, "Scene: built-in name, .json, .obj, .ply, .gltf or .glb (default: default)");
      app.add_option("--size", args->size, "Image size WxH (default 320x180)");
      app.add_option("--threads", args->threads, "Engine render threads (default: all hardware threads)");
      app.add_option("--spp", args->spp, "Samples per pixel of each timed one-shot image (default 8)");
      app.add_option("--repeats", args->repeats, "Timed repetitions, on and off alternating; the median is reported (default 5)");
      app.add_option("--seconds", args->seconds, "Seconds per engine throughput measurement (default 1)");
      app.add_flag("--json", args->json, "Print JSON instead of the table");
      app.add_option("--out", args->out, "Also write DIR/ablation.json and DIR/ablation.txt");
      return [args]() { return bench::run_ablation(*args); };
    });

}  // namespace
}  // namespace frameless::cli
