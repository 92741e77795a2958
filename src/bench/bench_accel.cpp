// `frameless bench accel`: the BVH against Parker's hybrid grid per scene (seed section 2): build
// time, memory and Mrays/s of each on the scene's camera rays and shadow rays, and the choice
// `--accel auto` makes from its work-count trial.
#include "bench/bench_accel.h"

#include <cstdio>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/scene/scene_finalize.h"
#include "frameless/cpu_clock.h"

namespace frameless::bench {
namespace {

struct Rays {
  std::vector<Ray> camera, shadow;
};

// Camera rays through pixel centres, and from each hit a shadow ray to each point light.
Rays scene_rays(const Scene& s, int w, int h) {
  Rays r;
  const CameraBasis b = make_camera_basis(s.camera, w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) r.camera.push_back(camera_ray(b, x + 0.5f, y + 0.5f));
  for (const Ray& ray : r.camera) {
    Hit hit;
    if (!s.accel.intersect(ray, hit)) continue;
    const Vec3 p = ray.org + hit.t * ray.dir;
    for (const Light& l : s.lights) {
      if (l.kind != LightKind::kPoint) continue;
      const Vec3 d = l.position - p;
      const float len = glm::length(d);
      if (!(len > 0.0f)) continue;
      Ray sh;
      sh.dir = d / len;
      sh.org = p + sh.dir * (1e-4f * len);
      sh.tmax = 0.999f * len;
      r.shadow.push_back(sh);
    }
  }
  return r;
}

// Median Mrays/s over repeats (thread CPU time: other processes on the machine do not count).
double mrays(const Scene& s, const std::vector<Ray>& rays, bool shadow, int repeats) {
  if (rays.empty()) return 0.0;
  std::vector<double> rates;
  uint64_t sink = 0;
  for (int k = 0; k < repeats; ++k) {
    const uint64_t t0 = thread_cpu_ns();
    for (const Ray& r : rays) {
      Hit h;
      sink += shadow ? s.accel.occluded(r) : s.accel.intersect(r, h);
    }
    const double sec = double(thread_cpu_ns() - t0) * 1e-9;
    rates.push_back(double(rays.size()) / sec * 1e-6);
  }
  if (sink == ~uint64_t(0)) std::printf(" ");  // keeps the loop from being optimised away
  return median(rates);
}

}  // namespace

int run_accel(const AccelOptions& a) {
  std::string error;
  int w = 0, h = 0;
  if (!parse_size(a.size, w, h, error)) return report_error(error);
  if (a.repeats < 1 || a.repeats > 100) return report_error("--repeats: must be 1..100");
  if (!a.out.empty() && !prepare_out_dir(a.out, error)) return report_error(error);
  // Both structures built on one thread (the grid's builder is serial): their build times are
  // compared side by side.
  const ScopedBuildExecutor one_thread({});
  nlohmann::json j = bench_header("accel", nullptr, "", {{"size", a.size}, {"repeats", a.repeats}});
  for (const std::string& spec : a.scenes) {
    bench_progress("accel", spec + ": loading");
    auto scene = load_scene_or_report(spec);
    if (!scene) return 2;
    nlohmann::json sj;
    sj["scene"] = spec;
    sj["primitives"] = scene->geometry.num_primitives();
    const Rays rays = scene_rays(*scene, w, h);  // the same rays for both structures
    sj["camera_rays"] = rays.camera.size();
    sj["shadow_rays"] = rays.shadow.size();
    for (AccelKind kind : {AccelKind::kBvh, AccelKind::kGrid}) {
      bench_progress("accel", spec + ": " + accel_kind_name(kind));
      set_accel(*scene, kind);
      const AccelStats& st = scene->accel.stats();
      sj[accel_kind_name(kind)] = {{"build_ms", st.build_ms},
                                   {"bytes", st.bytes},
                                   {"bytes_per_primitive", double(st.bytes) / std::max<double>(1, sj["primitives"].get<double>())},
                                   {"camera_mrays_per_s", mrays(*scene, rays.camera, false, a.repeats)},
                                   {"shadow_mrays_per_s", mrays(*scene, rays.shadow, true, a.repeats)}};
      if (st.structure != kind) sj[accel_kind_name(kind)]["note"] = "cut-out textures: the BVH is used";
    }
    bench_progress("accel", spec + ": auto");
    set_accel(*scene, AccelKind::kAuto);
    const AccelStats& st = scene->accel.stats();
    sj["auto"] = {{"choice", accel_kind_name(st.structure)},
                  {"trial_rays", st.trial_rays},
                  {"bvh_cost", st.bvh_cost},
                  {"grid_cost", st.grid_cost},
                  {"bvh_nodes", st.bvh_counts.nodes},
                  {"bvh_prims", st.bvh_counts.prims},
                  {"grid_nodes", st.grid_counts.nodes},
                  {"grid_prims", st.grid_counts.prims},
                  {"build_ms", st.build_ms}};
    const double bvh = sj["bvh"]["camera_mrays_per_s"], grid = sj["grid"]["camera_mrays_per_s"];
    sj["faster_on_camera_rays"] = grid > bvh ? "grid" : "bvh";
    j["scenes"].push_back(sj);
  }
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%-16s %-5s %10s %9s %12s %12s   auto\n", "scene", "accel", "build ms", "B/prim",
                "camera Mr/s", "shadow Mr/s");
    for (const auto& sj : j["scenes"])
      for (const char* k : {"bvh", "grid"}) {
        const auto& v = sj[k];
        std::printf("%-16s %-5s %10.1f %9.1f %12.2f %12.2f   %s\n",
                    sj["scene"].get<std::string>().c_str(), k, v["build_ms"].get<double>(),
                    v["bytes_per_primitive"].get<double>(), v["camera_mrays_per_s"].get<double>(),
                    v["shadow_mrays_per_s"].get<double>(),
                    std::string(k) == "bvh"
                        ? ("chooses " + sj["auto"]["choice"].get<std::string>()).c_str()
                        : ("(faster: " + sj["faster_on_camera_rays"].get<std::string>() + ")").c_str());
      }
  }
  if (!a.out.empty() && !write_json(a.out + "/accel.json", j, error)) return report_error(error);
  return 0;
}

}  // namespace frameless::bench
