// `frameless bench reproject`: its flags; the benchmark is bench::run_reproject
// (src/bench/bench_reproject.h).
#include <memory>

#include "bench/bench_reproject.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

const bool bench_reproject_registered = register_command(
    "bench", "reproject",
    "The display's reprojection alone, per camera change, along its Hilbert curve, in the engine's slot order and in pixel order, with its phases",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::ReprojectOptions>();
      app.add_option("scene", args->scene, "Scene whose primary hits are moved")->capture_default_str();
      app.add_option("--size", args->size, "Image size WxH")->capture_default_str();
      app.add_option("--threads", args->threads, "Render threads whose slot order is measured (0: all cores)")
          ->capture_default_str();
      app.add_option("--degrees", args->degrees, "Orbit per camera change")->capture_default_str();
      app.add_option("--changes", args->changes, "Timed camera changes per order (median)")->capture_default_str();
      app.add_option("--order", args->order, "curve (the display's), slots (the engine's), pixels or all")->capture_default_str();
      app.add_option("--evict", args->evict_mb,
                     "Megabytes of other memory written between changes, untimed, as render threads write "
                     "their pixels' states and points between the display's changes (0: none; 88 is theirs "
                     "at 1280x720)")
          ->capture_default_str();
      app.add_flag("--json", args->json, "Print JSON instead of text");
      return [args]() { return bench::run_reproject(*args); };
    });

}  // namespace
}  // namespace frameless::cli
