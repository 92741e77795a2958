// `frameless bench scale`: its flags; the benchmark is bench::run_scale (src/bench/bench_scale.h).
#include <memory>

#include "bench/bench_scale.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_scale_registered = register_command(
    "bench", "scale", "spheres:N up to 3.5e7: build time, memory, samples/s, sub-linear ray cost",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::ScaleOptions>();
      app.add_option("--out", args->out, "Output directory (scale.json, scale.csv, scale.png)")
          ->required();
      app.add_option("--max-n", args->max_n,
                     "Largest N to run (default 35000000; 35M spheres take about a minute and 1.3 GB)");
      app.add_option("--n", args->ns, "Sphere counts (default 1e3,1e4,...,1e7,3.5e7)")
          ->delimiter(',');
      app.add_option("--size", args->size,
                     "Image size WxH for samples/s and ray cost (default 160x120)");
      app.add_option("--spp", args->spp, "Samples per pixel for samples/s (default 4)");
      app.add_option("--threads", args->threads, "Threads (default: all hardware threads)");
      app.add_flag("--quick", args->quick, "Smoke mode: N up to 1e5, 96x72, 2 spp");
      return [args]() { return bench::run_scale(*args); };
    });

}  // namespace
}  // namespace frameless::cli
