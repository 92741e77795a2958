// `frameless bench patches`: spline patches ray traced directly (seed section 3.3) against the
// same patches tessellated into triangles: samples/s of each, the tessellation's image error
// against the direct render, the finest tessellation needed to match it, and Broyden's iteration
// counts (the seed: "usually fewer than three iterations").
#include "bench/bench_patches.h"

#include <cstdio>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/scene/scene_finalize.h"
#include "frameless/image_error.h"

namespace frameless::bench {
namespace {

// Replaces every patch by an n x n grid of quads (two triangles each) with exact normals.
void tessellate(Scene& s, int n) {
  Geometry& g = s.geometry;
  // The other meshes get their face normals per vertex, so every vertex has a shading normal.
  if (g.normals.size() != g.positions.size()) {
    g.normals.assign(g.positions.size(), Vec3(0.0f, 1.0f, 0.0f));
    for (const UVec3& t : g.triangles) {
      const Vec3 n = glm::cross(g.positions[t.y] - g.positions[t.x], g.positions[t.z] - g.positions[t.x]);
      if (glm::dot(n, n) > 0.0f)
        for (int k = 0; k < 3; ++k) g.normals[t[k]] = glm::normalize(n);
    }
  }
  for (uint32_t i = 0; i < g.num_patches(); ++i) {
    const BezierPatch& p = g.patches[i].patch();
    const uint32_t base = uint32_t(g.positions.size());
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) {
        const float u = float(x) / float(n), v = float(y) / float(n);
        g.positions.push_back(bezier_eval(p, u, v));
        g.normals.push_back(bezier_normal(p, u, v));
      }
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const uint32_t a = base + uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1) + 1,
                       d = a + uint32_t(n + 1);
        g.triangles.push_back(UVec3(a, b, c));
        g.triangles.push_back(UVec3(a, c, d));
        g.triangle_material.push_back(g.patch_material[i]);
        g.triangle_material.push_back(g.patch_material[i]);
      }
  }
  g.patches.clear();
  g.patch_material.clear();
  g.patch_shadow_grid.clear();
  g.triangle_opposite.clear();
  finalize_scene(s);
}

}  // namespace

int run_patches(const PatchesOptions& a) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(a.size, w, h, error)) return report_error(error);
  if (a.spp < 1 || a.spp > 4096) return report_error("--spp: must be 1..4096");
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be 1..100");
  for (int n : a.levels)
    if (n < 1 || n > 256) return report_error("--levels: each must be 1..256");
  if (!a.out.empty() && !prepare_out_dir(a.out, error)) return report_error(error);
  auto scene = load_scene_or_report(a.scene, &a.shadows);
  if (!scene) return 2;
  if (scene->geometry.num_patches() == 0) return report_error(a.scene + ": the scene has no spline patches");
  nlohmann::json j = bench_header("patches", scene.get(), a.scene,
                                  {{"size", a.size}, {"spp", a.spp}, {"repeats", a.repeats}});
  const double samples = double(w) * h * a.spp;
  auto timed = [&](const Scene& s, std::vector<float>& image) {
    std::vector<double> t;
    for (int k = 0; k < a.repeats; ++k) {
      double sec = 0;
      image = render_one_thread(s, w, h, a.spp, sec);
      t.push_back(sec);
    }
    return samples / median(t);
  };
  bench_progress("patches", "direct");
  std::vector<float> direct;
  const double direct_rate = timed(*scene, direct);
  // Broyden's work on the camera rays (one pass, outside the timing).
  PatchHitStats st;
  const CameraBasis b = make_camera_basis(scene->camera, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Ray r = camera_ray(b, x + 0.5f, y + 0.5f);
      for (const PatchSurface& p : scene->geometry.patches) {
        float t, u, v;
        p.intersect(r, 0.0f, kInfinity, t, u, v, &st);
      }
    }
  j["direct"] = {{"patches", scene->geometry.num_patches()},
                 {"depth", scene->geometry.patches[0].depth()},
                 {"samples_per_s", direct_rate},
                 {"broyden", {{"leaf_tests", st.leaf_tests}, {"solves", st.solves},
                              {"converged", st.converged}, {"iterations", st.iterations},
                              {"mean_iterations_per_converged_solve",
                               st.converged ? double(st.iterations) / double(st.converged) : 0.0}}}};
  // Equal visual accuracy: the coarsest tessellation whose image differs from the direct one by
  // less than half an 8-bit level (RMSE < 0.5 / 255).
  constexpr double kInvisible = 0.5 / 255.0;
  int match = -1;
  for (int n : a.levels) {
    bench_progress("patches", "tessellated " + std::to_string(n) + "x" + std::to_string(n));
    auto tess = load_scene_or_report(a.scene);
    if (!tess) return 2;
    tessellate(*tess, n);
    if (!a.shadows.apply(*tess, error)) return report_error(error);
    std::vector<float> img;
    const double rate = timed(*tess, img);
    const double rmse = image_error(img, direct, size_t(w) * h).rmse;
    if (match < 0 && rmse < kInvisible) match = n;
    j["tessellated"].push_back({{"level", n}, {"triangles", tess->geometry.num_triangles()},
                                {"samples_per_s", rate}, {"direct_over_tessellated", direct_rate / rate},
                                {"rmse_vs_direct", rmse}});
  }
  j["equal_accuracy_level"] = match > 0 ? nlohmann::json(match) : nlohmann::json(nullptr);
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    const auto& d = j["direct"];
    std::printf("%s (%s, %d spp, 1 thread, median of %d)\n", a.scene.c_str(), a.size.c_str(), a.spp,
                a.repeats);
    std::printf("  direct: %d patches, depth %d: %.0f samples/s; Broyden %.2f iterations per "
                "converged solve (%llu solves)\n",
                d["patches"].get<int>(), d["depth"].get<int>(), direct_rate,
                d["broyden"]["mean_iterations_per_converged_solve"].get<double>(),
                (unsigned long long)st.solves);
    std::printf("  %8s %10s %14s %12s %14s\n", "level", "triangles", "samples/s", "direct/tess",
                "RMSE vs direct");
    for (const auto& t : j["tessellated"])
      std::printf("  %8d %10llu %14.0f %11.2fx %14.5f\n", t["level"].get<int>(),
                  (unsigned long long)t["triangles"].get<uint64_t>(), t["samples_per_s"].get<double>(),
                  t["direct_over_tessellated"].get<double>(), t["rmse_vs_direct"].get<double>());
    if (match > 0)
      std::printf("  equal visual accuracy (RMSE < 0.5/255) from level %d\n", match);
    else
      std::printf("  no level reached RMSE < 0.5/255\n");
  }
  if (!a.out.empty() && !write_json(a.out + "/patches.json", j, error)) return report_error(error);
  return 0;
}

}  // namespace frameless::bench
