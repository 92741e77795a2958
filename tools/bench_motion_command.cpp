// `frameless bench motion`: its flags; the benchmark is bench::run_motion
// (src/bench/bench_motion.h).
#include <memory>

#include "bench/bench_motion.h"
#include "bench/bench_motion_sweep.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_motion_registered = register_command(
    "bench", "motion",
    "Moving camera: error of every displayed image vs the converged image for that instant",
    [](CLI::App& app) {
      auto args = std::make_shared<bench::MotionOptions>();
      app.add_option("scene", args->scene,
                     "Scene: built-in name, .json, .obj, .ply, .gltf or .glb (default: default)");
      add_shadow_flags(app, args->shadows);
      app.add_option("--out", args->out, "Output directory (motion.json, motion.csv, motion.png)")
          ->required();
      app.add_option("--size", args->size, "Image size WxH (default 320x240)");
      app.add_option("--threads", args->threads, "Render threads (default: all hardware threads)");
      app.add_option("--move-seconds", args->move_seconds, "Length of the camera move (default 3)");
      app.add_option("--hold-seconds", args->hold_seconds,
                     "Still camera before the move (default 1)");
      app.add_option("--tail-seconds", args->tail_seconds,
                     "Still camera after the move (default 0.5)");
      app.add_option("--camera-hz", args->camera_hz,
                     "Camera input rate: poses per second (default 10)");
      app.add_option("--refresh", args->refresh, "Display refresh in Hz (default 30)");
      app.add_option("--orbit", args->orbit, "Degrees orbited during the move (default 40)");
      app.add_option("--dolly", args->dolly, "Eye-distance factor over the move (default 0.85)");
      app.add_option("--alphas", args->alphas,
                     "Frameless blend weights to compare (default 0.25,0.5,1)")
          ->delimiter(',');
      app.add_option("--update-percents", args->percents,
                     "Update percentages to compare (default 0.1,1,10)")
          ->delimiter(',');
      app.add_option("--sample-fractions", args->sample_fractions,
                     "Also run reprojection + temporal weights capped at these fractions of "
                     "conventional's samples/s: the samples needed for its error (default "
                     "0.5,0.25,0.125; 0 runs none)")
          ->delimiter(',');
      app.add_option("--render-nice", args->render_nice,
                     "Render threads' nice value above the display's, 0..19 (default " +
                         std::to_string(kDefaultRenderNice) + ")");
      app.add_option("--budget", args->budget,
                     "Reprojection budget of the budgeted row, a fraction of one core (default "
                     "0.15: the display thread within 25 % in bench engine's 1280x720 move)");
      app.add_option("--alpha", args->alpha,
                     "Default frameless alpha: the headline setting (default 0.5)");
      app.add_option("--update-percent", args->percent, "Default update percentage (default 1)");
      app.add_option("--ref-spp", args->ref_spp,
                     "Reference samples per pixel per pose (default 32)");
      app.add_option(
          "--repeats", args->repeats,
          "Runs of every setting, interleaved; time averages are their mean (default 2)");
      app.add_option(
          "--cache", args->cache,
          "Reference cache directory (default $XDG_CACHE_HOME/frameless/references or OUT/cache)");
      app.add_flag("--quick", args->quick,
                   "Smoke mode: 160x120, 1.5 s move, 8-spp references, fewer settings, one repeat");
      auto sweep = std::make_shared<bench::MotionSweepOptions>();
      auto sweeping = std::make_shared<bool>(false);
      app.add_flag("--sweep", *sweeping,
                   "Sweep the regime (conventional frame time / camera interval) over scenes and "
                   "sizes; OUT/sweep.json, sweep.png");
      app.add_option("--sweep-scenes", sweep->scenes, "Scenes of the sweep (default default,bunny)")
          ->delimiter(',');
      app.add_option("--sweep-sizes", sweep->sizes,
                     "Sizes of the sweep (default 160x120,320x240,640x360,960x540)")
          ->delimiter(',');
      return [args, sweep, sweeping]() {
        if (!*sweeping) return bench::run_motion(*args);
        sweep->base = *args;
        return bench::run_motion_sweep(*sweep);
      };
    });

}  // namespace
}  // namespace frameless::cli
