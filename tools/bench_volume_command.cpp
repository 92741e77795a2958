// `frameless bench volume`: its flags; the benchmark is bench::run_volume (src/bench/bench_volume.h).
#include <memory>

#include "bench/bench_volume.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_volume_registered = register_command(
    "bench", "volume",
    "Volumes: a Visible-Female-sized CT phantom loaded, as an isosurface, through the volume shader and by MIP",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::VolumeOptions>();
      app.add_option("--dims", args->dims, "Phantom voxels NXxNYxNZ (default 512x512x1734: the Visible Female's size)");
      app.add_option("--size", args->size, "Image size WxH (default 512x512)");
      app.add_option("--threads", args->threads, "Render threads (default: all)");
      app.add_option("--spp", args->spp, "Samples per pixel of the timed frames (default 1)");
      app.add_option("--seconds", args->seconds, "Length of each live engine run (default 3)");
      app.add_option("--out", args->out, "Output directory: volume.json and a picture per mode (and the raw file meanwhile)");
      app.add_flag("--keep", args->keep, "Keep the phantom's raw file");
      app.add_flag("--json", args->json, "Print JSON instead of the table");
      app.add_flag("--quick", args->quick, "Smoke mode: a 128^3 phantom at 128x128, short runs");
      return [args]() { return bench::run_volume(*args); };
    });

}  // namespace
}  // namespace frameless::cli
