// `frameless bench rays`: its flags; the benchmark is bench::run_rays (src/bench/bench_rays.h).
#include <memory>

#include "bench/bench_rays.h"
#include "tools/command_registry.h"
#include "tools/tool_options.h"

namespace frameless::cli {
namespace {

const bool bench_rays_registered = register_command(
    "bench", "rays",
    "Ray throughput of the BVH per kind of ray, side by side with Embree when built with it; "
    "several scenes make one table and plot",
    [](CLI::App& app) {
      auto a = std::make_shared<bench::RaysOptions>();
      app.add_option("scenes", a->scenes,
                     "built-in names, .json scenes or .obj/.ply/.gltf/.glb models, measured one after the other")
          ->capture_default_str();
      app.add_option("--out", a->out, "also write DIR/rays.json (every run), DIR/rays.csv (a row per scene and kind of ray) and the plot DIR/rays.png of the ratios to Embree (of Mrays/s without it; its data and script: rays.dat, rays.gp)");
      add_shadow_flags(app, a->shadows);
      app.add_option("--size", a->size, "image size WxH")->capture_default_str();
      app.add_option("--threads", a->threads,
                     "threads for the parallel figures (default: all cores)");
      app.add_option("--reps", a->reps, "repetitions; the best of them is reported")
          ->capture_default_str();
      app.add_flag("--json", a->json, "print one JSON object instead of a table (several scenes: their objects under \"runs\")");
      app.add_flag("--no-embree", a->no_embree, "skip the Embree comparison (when built with it)");
      app.add_flag("--embree-robust", a->embree_robust,
                   "give Embree's scenes RTC_SCENE_FLAG_ROBUST (its mode that keeps accuracy, the like of our "
                   "watertight test and conservative boxes) instead of its default fast mode; nothing without Embree");
      app.add_option("--embree-quality", a->embree_quality,
                     "Embree's build quality: low (its two-level index for dynamic scenes), medium (its default, binned SAH) or high (with spatial "
                     "splits, the builder a user picks for static scenes when rays matter more than build time)")
          ->capture_default_str();
      app.add_flag("--opaque", a->opaque,
                   "ignore cut-out (alpha) surfaces, as the Embree comparison does");
      add_camera_flags(app, a->camera);
      return [a] { return bench::run_rays(*a); };
    });

}  // namespace
}  // namespace frameless::cli
