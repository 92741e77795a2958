// `frameless bench shadows`: what shadows and ambient cost per sample and how accurate they are.
// For each scene: 1-thread CPU time per image with hard, soft (single sample), area-sampled and
// transparent shadows, and with constant against hemisphere ambient (seed 3.1.1 says "not
// measurably slower"); RMSE of soft and hard against the area-sampled reference.
#include "bench/bench_shadows.h"

#include <cstdio>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/scene/scene_finalize.h"
#include "frameless/cpu_clock.h"
#include "frameless/image_error.h"
#include "frameless/tile_render.h"

namespace frameless::bench {
namespace {


struct Variant {
  const char* name;
  ShadowMode mode;
  bool transparent;
  AmbientKind ambient;  // kNone: keep the scene's
};

}  // namespace

int run_shadows(const ShadowBenchOptions& a) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(a.size, w, h, error)) return report_error(error);
  if (a.spp < 1 || a.spp > 4096) return report_error("--spp: must be 1..4096");
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be 1..100");
  if (a.reference_samples < 1 || a.reference_samples > 4096)
    return report_error("--reference-samples: must be 1..4096");
  if (!(a.light_radius > 0.0f)) return report_error("--light-radius: must be > 0");
  if (!a.out.empty() && !prepare_out_dir(a.out, error)) return report_error(error);
  const Variant variants[] = {
      {"hard", ShadowMode::kHard, false, AmbientKind::kNone},
      {"soft", ShadowMode::kSoft, false, AmbientKind::kNone},
      {"area16", ShadowMode::kArea, false, AmbientKind::kNone},
      {"beam", ShadowMode::kBeam, false, AmbientKind::kNone},
      {"hard+transparent", ShadowMode::kHard, true, AmbientKind::kNone},
      {"soft+transparent", ShadowMode::kSoft, true, AmbientKind::kNone},
      {"soft+constant-ambient", ShadowMode::kSoft, false, AmbientKind::kConstant},
      {"soft+hemisphere-ambient", ShadowMode::kSoft, false, AmbientKind::kHemisphere},
  };
  nlohmann::json j = bench_header("shadows", nullptr, "", {{"size", a.size}, {"spp", a.spp},
                                                            {"repeats", a.repeats},
                                                            {"reference_samples", a.reference_samples},
                                                            {"light_radius_for_point_lights", a.light_radius}});
  for (const std::string& spec : a.scenes) {
    auto scene = load_scene_or_report(spec);
    if (!scene) return 2;
    // Point lights get a radius so that there is a penumbra to compute.
    for (Light& l : scene->lights)
      if (l.kind == LightKind::kPoint && l.radius <= 0.0f) l.radius = a.light_radius;
    const Ambient original = scene->ambient;
    nlohmann::json sj;
    sj["scene"] = spec;
    bench_progress("shadows", spec + ": area reference");
    set_shadow_settings(*scene, ShadowMode::kArea, a.reference_samples, false);
    double unused = 0;
    const std::vector<float> reference = render_one_thread(*scene, w, h, a.spp, unused);
    std::vector<std::vector<double>> times(std::size(variants));
    std::vector<std::vector<float>> images(std::size(variants));
    // Variants interleave within each repeat (no drift bias between them).
    for (int k = 0; k < a.repeats; ++k)
      for (size_t v = 0; v < std::size(variants); ++v) {
        const Variant& var = variants[v];
        bench_progress("shadows", spec + ": " + var.name);
        scene->ambient = original;
        if (var.ambient != AmbientKind::kNone) scene->ambient.kind = var.ambient;
        set_shadow_settings(*scene, var.mode, 16, var.transparent);
        double t = 0;
        images[v] = render_one_thread(*scene, w, h, a.spp, t);
        times[v].push_back(t);
      }
    scene->ambient = original;
    const double samples = double(w) * h * a.spp;
    const double hard_ns = median(times[0]) / samples * 1e9;
    for (size_t v = 0; v < std::size(variants); ++v) {
      const double ns = median(times[v]) / samples * 1e9;
      const double rmse = image_error(images[v], reference, size_t(w) * h).rmse;
      sj["variants"][variants[v].name] = {{"ns_per_sample", ns},
                                          {"relative_to_hard", ns / hard_ns},
                                          {"rmse_vs_area_reference", rmse}};
    }
    const auto& vj = sj["variants"];
    sj["soft_over_hard_cost"] = vj["soft"]["relative_to_hard"];
    sj["hemisphere_over_constant_cost"] = vj["soft+hemisphere-ambient"]["ns_per_sample"].get<double>() /
                                          vj["soft+constant-ambient"]["ns_per_sample"].get<double>();
    j["scenes"].push_back(sj);
  }
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    for (const auto& sj : j["scenes"]) {
      std::printf("scene %s (%s, %d spp, 1 thread, median of %d)\n",
                  sj["scene"].get<std::string>().c_str(), a.size.c_str(), a.spp, a.repeats);
      std::printf("  %-24s %10s %9s %12s\n", "variant", "ns/sample", "vs hard", "RMSE vs area");
      for (const auto& [name, v] : sj["variants"].items())
        std::printf("  %-24s %10.1f %8.2fx %12.5f\n", name.c_str(), v["ns_per_sample"].get<double>(),
                    v["relative_to_hard"].get<double>(), v["rmse_vs_area_reference"].get<double>());
      std::printf("  soft/hard cost %.2fx; hemisphere/constant ambient cost %.3fx\n",
                  sj["soft_over_hard_cost"].get<double>(),
                  sj["hemisphere_over_constant_cost"].get<double>());
    }
  }
  if (!a.out.empty() && !write_json(a.out + "/shadows.json", j, error)) return report_error(error);
  return 0;
}

}  // namespace frameless::bench
