// `frameless bench dynamic`: what moving objects cost. RTRT keeps dynamic objects out of the
// acceleration structure and tests each per ray (seed section 4: "this only works for limited
// numbers"); this measures samples/s against their number and how many double the cost.
#include "bench/bench_dynamic.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/base/rng.h"
#include "core/scene/scene_finalize.h"

namespace frameless::bench {
namespace {

// Adds n bouncing balls spread over the scene's floor area (seeded: the same balls every run).
void add_bouncing_balls(Scene& s, int n) {
  Vec3 lo, hi;
  geometry_bounds(s.geometry, lo, hi);
  const float size = max_component(hi - lo), r = 0.03f * size;
  Material m;
  m.name = "bench-ball";
  m.cls = MaterialClass::kPolished;
  m.kd = Vec3(0.8f, 0.3f, 0.2f);
  m.kh = Vec3(0.5f);
  s.materials.push_back(m);
  Rng rng(0xd1);
  for (int i = 0; i < n; ++i) {
    DynamicObject o;
    o.name = "ball" + std::to_string(i);
    o.sphere.center = Vec3(lo.x + (hi.x - lo.x) * rng.next_float(), lo.y + r,
                           lo.z + (hi.z - lo.z) * rng.next_float());
    o.sphere.radius = r;
    o.material = uint16_t(s.materials.size() - 1);
    o.motion.kind = MotionKind::kBounce;
    o.motion.bounce = Bounce{0.3f * size * rng.next_float(), 0.5f + rng.next_float(), rng.next_float()};
    s.dynamic.push_back(o);
  }
  finalize_scene(s);
}

}  // namespace

int run_dynamic(const DynamicOptions& a) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(a.size, w, h, error)) return report_error(error);
  if (a.spp < 1 || a.spp > 4096) return report_error("--spp: must be 1..4096");
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be 1..100");
  for (int n : a.counts)
    if (n < 0 || n > 65536) return report_error("--counts: each must be 0..65536");
  if (!a.out.empty() && !prepare_out_dir(a.out, error)) return report_error(error);
  nlohmann::json j = bench_header("dynamic", nullptr, "", {{"scene", a.scene}, {"size", a.size},
                                                            {"spp", a.spp}, {"repeats", a.repeats}});
  const double samples = double(w) * h * a.spp;
  double base_ns = 0.0, doubling = NAN, prev_n = 0.0, prev_ratio = 1.0;
  for (int n : a.counts) {
    auto scene = load_scene_or_report(a.scene);
    if (!scene) return 2;
    add_bouncing_balls(*scene, n);
    std::vector<double> times;
    for (int k = 0; k < a.repeats; ++k) {
      bench_progress("dynamic", std::to_string(n) + " objects");
      double t = 0;
      render_one_thread(*scene, w, h, a.spp, t);
      times.push_back(t);
    }
    const double ns = median(times) / samples * 1e9;
    if (j["points"].empty()) base_ns = ns;
    const double ratio = ns / base_ns;
    // First count where the cost reaches twice the static scene's, interpolated linearly.
    if (std::isnan(doubling) && ratio >= 2.0 && !j["points"].empty())
      doubling = prev_n + (2.0 - prev_ratio) / (ratio - prev_ratio) * (double(n) - prev_n);
    prev_n = n;
    prev_ratio = ratio;
    j["points"].push_back({{"objects", n}, {"ns_per_sample", ns}, {"samples_per_s", 1e9 / ns},
                           {"relative_to_first", ratio}});
  }
  j["objects_to_double_cost"] = std::isnan(doubling) ? nlohmann::json(nullptr) : nlohmann::json(doubling);
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("scene %s + N bouncing balls (%s, %d spp, 1 thread, median of %d)\n", a.scene.c_str(),
                a.size.c_str(), a.spp, a.repeats);
    std::printf("  %8s %12s %14s %10s\n", "objects", "ns/sample", "samples/s", "relative");
    for (const auto& p : j["points"])
      std::printf("  %8d %12.1f %14.0f %9.2fx\n", p["objects"].get<int>(), p["ns_per_sample"].get<double>(),
                  p["samples_per_s"].get<double>(), p["relative_to_first"].get<double>());
    if (std::isnan(doubling))
      std::printf("  the cost did not double within these counts\n");
    else
      std::printf("  the cost doubles at about %.0f dynamic objects\n", doubling);
  }
  if (!a.out.empty() && !write_json(a.out + "/dynamic.json", j, error)) return report_error(error);
  return 0;
}

}  // namespace frameless::bench
