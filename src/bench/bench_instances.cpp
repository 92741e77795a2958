// `frameless bench instances`: the cost of moving instances while you look (OpenRT). For moves of
// one instance, 1 % and all of them (small steps: a refit), and a scatter (every instance to
// another's place: the refit loosens the tree past kRebuildFactor, so it is rebuilt), the time
// of one update (copy of the published top level, refit, rebuild), next to a build of the top
// level from scratch, and what a refit costs the rays: shadow-free primary hits per second
// through the moved top against a freshly built one.
#include "bench/bench_instances.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/bench_options.h"
#include "core/accel/instance_top.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace frameless::bench {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Camera rays at size x size through the top `top` (flat geometry included); hits per second.
double mrays(const Scene& s, const InstanceTop& top, int size) {
  const CameraBasis b = make_camera_basis(s.camera, size, size);
  const auto t0 = std::chrono::steady_clock::now();
  uint64_t hits = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      Hit h;
      hits += s.accel.intersect(camera_ray(b, float(x) + 0.5f, float(y) + 0.5f), h, &top) ? 1 : 0;
    }
  const double ms = ms_since(t0);
  return hits > 0 ? double(size) * size / (ms * 1e3) : 0.0;
}

// A step of about a hundredth of the instance's own size: the kind of move a drag makes.
std::vector<InstanceMove> nudge(const InstanceTop& top, const std::vector<uint32_t>& which, float k) {
  std::vector<InstanceMove> moves;
  for (uint32_t d : which) {
    const uint32_t p = top.position[d];
    Affine a = top.instances[p].to_world;
    a.t += k * 0.01f * (top.hi[p] - top.lo[p]);
    moves.push_back({d, a});
  }
  return moves;
}

}  // namespace

int run_instances(const InstancesOptions& a) {
  std::unique_ptr<Scene> scene = load_scene_or_report(a.scene, nullptr);
  if (!scene) return 2;
  const std::shared_ptr<const InstanceTop> top = scene->accel.instance_top();
  if (!top) return report_error(a.scene + ": the scene has no instances");
  const uint32_t n = uint32_t(top->position.size());
  std::vector<uint32_t> one{n / 2}, some, all;
  for (uint32_t i = 0; i < n; ++i) {
    all.push_back(i);
    if (i % 100 == 0) some.push_back(i);
  }
  std::vector<InstanceMove> scatter;  // instance i goes to instance (i * 7919 + 1) mod n's place
  for (uint32_t i = 0; i < n; ++i)
    scatter.push_back({i, top->instances[top->position[(uint64_t(i) * 7919u + 1u) % n]].to_world});
  struct Case {
    const char* name;
    std::vector<InstanceMove> moves;
  } cases[] = {{"1 instance", nudge(*top, one, 1.0f)},
               {"1% of instances", nudge(*top, some, 1.0f)},
               {"all instances", nudge(*top, all, 1.0f)},
               {"scatter (all, far)", scatter}};
  const bool progress = show_progress() && !a.json;
  nlohmann::ordered_json out;
  out["scene"] = a.scene;
  out["instances"] = n;
  out["meshes"] = top->meshes->size();
  out["top_nodes"] = top->nodes.size();
  out["top_bytes"] = top->bytes();
  double build_ms = 1e30;
  for (int r = 0; r < a.reps; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    auto fresh = build_instance_top(scene->geometry.instances, scene->geometry.instance_meshes);
    build_ms = std::min(build_ms, ms_since(t0));
  }
  out["build_ms"] = build_ms;
  if (!a.json)
    std::printf("%s: %u instances of %zu meshes; top level %zu nodes, %.1f MB; built from scratch in %.2f ms\n",
                a.scene.c_str(), n, top->meshes->size(), top->nodes.size(), double(top->bytes()) / 1e6, build_ms);
  if (!a.json)
    std::printf("  %-20s %8s %9s %9s %10s %9s %9s %12s\n", "update (best of reps)", "moved", "copy ms",
                "refit ms", "rebuild ms", "total ms", "rebuilt", "rays moved/fresh");
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const Case& c : cases) {
    InstanceUpdate best;
    double best_total = 1e30;
    std::shared_ptr<InstanceTop> moved;
    for (int r = 0; r < a.reps; ++r) {
      if (progress) std::fprintf(stderr, "\r%s: repetition %d/%d", c.name, r + 1, a.reps);
      InstanceUpdate u;
      auto m = move_instances(*top, c.moves, {}, &u);
      if (!m) return report_error(m.error().message);
      const double total = u.copy_ms + u.refit_ms + u.rebuild_ms;
      if (total < best_total) best_total = total, best = u;
      moved = *m;
    }
    // What a refit costs the rays: the moved top against one built over the same transforms.
    std::vector<Instance> placed = moved->instances;
    std::vector<Instance> declared(n);
    for (uint32_t k = 0; k < n; ++k) declared[moved->declared[k]] = placed[k];
    auto fresh = build_instance_top(declared, scene->geometry.instance_meshes);
    double ray_moved = 0.0, ray_fresh = 0.0;  // alternating, best of reps: load hits both alike
    for (int r = 0; r < a.reps; ++r) {
      ray_moved = std::max(ray_moved, mrays(*scene, *moved, a.size));
      ray_fresh = std::max(ray_fresh, mrays(*scene, *fresh, a.size));
    }
    const double ratio = ray_moved / std::max(1e-9, ray_fresh);
    if (progress) std::fprintf(stderr, "\r%*s\r", 50, "");
    nlohmann::ordered_json j;
    j["update"] = c.name;
    j["moved"] = best.moved;
    j["copy_ms"] = best.copy_ms;
    j["refit_ms"] = best.refit_ms;
    j["rebuild_ms"] = best.rebuild_ms;
    j["total_ms"] = best_total;
    j["rebuilt"] = best.rebuilt;
    j["rays_moved_over_fresh"] = ratio;
    rows.push_back(j);
    if (!a.json)
      std::printf("  %-20s %8zu %9.2f %9.2f %10.2f %9.2f %9s %12.2f\n", c.name, best.moved, best.copy_ms,
                  best.refit_ms, best.rebuild_ms, best_total, best.rebuilt ? "yes" : "no", ratio);
  }
  out["updates"] = rows;
  if (a.json) std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace frameless::bench
