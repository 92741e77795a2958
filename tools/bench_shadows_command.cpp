// `frameless bench shadows`: its flags; the benchmark is bench::run_shadows
// (src/bench/bench_shadows.h).
#include <memory>

#include "bench/bench_shadows.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_shadows_registered = register_command(
    "bench", "shadows",
    "Cost and accuracy of hard, single-sample soft, area-sampled and transparent shadows, and of "
    "the hemisphere ambient",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::ShadowBenchOptions>();
      app.add_option("scenes", args->scenes, "Scenes (default: default balls)");
      app.add_option("--size", args->size, "Image size WxH (default 256x144)");
      app.add_option("--spp", args->spp, "Samples per pixel of each timed image (default 4)");
      app.add_option("--repeats", args->repeats, "Timed repetitions; the median is reported (default 5)");
      app.add_option("--reference-samples", args->reference_samples,
                     "Shadow rays per light of the area-sampled reference (default 64)");
      app.add_option("--light-radius", args->light_radius,
                     "Radius given to point lights so they cast a penumbra (default 0.5)");
      app.add_flag("--json", args->json, "Print JSON instead of the table");
      app.add_option("--out", args->out, "Also write DIR/shadows.json");
      return [args]() { return bench::run_shadows(*args); };
    });

}  // namespace
}  // namespace frameless::cli
