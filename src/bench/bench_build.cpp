// `frameless bench build`: BVH build time per scene, serial and through a parallel_for of N
// std::threads, side by side with Embree's build (rtcCommitScene, its default medium quality) on
// a device with 1 and with N threads, plus the quality of our tree (SAH cost, nodes, depth) and
// whether the parallel build gave the same tree. An instanced scene's shared meshes are built
// before either clock starts (at load for us, as Embree scenes for it): both time the flat
// geometry and the top level over the instances.
#include "bench/bench_build.h"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_options.h"
#include "core/accel/bvh_build.h"
#include "core/accel/bvh_build_spheres.h"
#include "core/scene/scene.h"

#if defined(FRAMELESS_HAVE_EMBREE)
#include "bench/bench_rays_embree.h"
#endif

namespace frameless::bench {
namespace {

// Puts each primitive kind in a fixed pseudo-random order (materials and per-triangle data
// travel along): an input without spatial order, the hardest case for branch prediction.
void shuffle_primitives(Geometry& g) {
  uint64_t state = 0x9e3779b97f4a7c15ull;
  auto next = [&state](size_t bound) {  // splitmix64, reduced to [0, bound)
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return size_t((z ^ (z >> 31)) % bound);
  };
  auto permute = [&](size_t n, auto&&... arrays) {
    for (size_t i = n; i > 1; --i) {
      const size_t j = next(i);
      auto swap_in = [&](auto& v) {
        if (v.size() == n) std::swap(v[i - 1], v[j]);
      };
      (swap_in(arrays), ...);
    }
  };
  permute(g.triangles.size(), g.triangles, g.triangle_material, g.triangle_opposite);
  permute(g.spheres.size(), g.spheres, g.sphere_material);
  permute(g.patches.size(), g.patches, g.patch_material);
}

double process_cpu_ms() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// Best (smallest) wall and process CPU times over repetitions, in ms.
struct Best {
  double wall = 1e30, cpu = 1e30;
  void add(double w, double c) {
    wall = std::min(wall, w);
    cpu = std::min(cpu, c);
  }
};

// One timed Accel::build (BVH) on a fresh copy of g: what a scene load waits for.
void time_accel_build(const Geometry& g, const AccelConfig& config, Best& best) {
  Geometry copy = g;
  Accel accel;
  const double cpu = process_cpu_ms();
  const auto start = std::chrono::steady_clock::now();
  accel.build(copy, config);
  const double wall =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  best.add(wall, process_cpu_ms() - cpu);
}

// Our tree over g as Accel::build makes it (the same primitive references), for its quality and
// the serial/parallel comparison.
Bvh8 build_tree(const Geometry& g, const AccelConfig& config) {
  if (g.num_triangles() == 0 && g.num_patches() == 0) {
    Geometry c = g;  // the sphere build sorts in place
    return build_bvh8_spheres(c.spheres, c.sphere_material, config);
  }
  const uint32_t nt = g.num_triangles(), ns = g.num_spheres();
  PrimRefArray refs = make_prim_refs(g, config);
  return build_bvh8(refs.data(), refs.size(), nt, config, nt + ns);
}

// Surface-area cost of an 8-wide tree relative to its root box: over nodes, area(node) /
// area(root) (one 8-wide box test each), plus over leaves area(leaf) / area(root) times the
// primitives in it (one test each). Lower is better: a proxy for traversal cost.
double sah_cost(const std::vector<Bvh8Node>& nodes) {
  if (nodes.empty()) return 0.0;
  auto half_area = [](const Bvh8Node& n, int i) {
    const double dx = double(n.bounds[1][i]) - n.bounds[0][i];
    const double dy = double(n.bounds[3][i]) - n.bounds[2][i];
    const double dz = double(n.bounds[5][i]) - n.bounds[4][i];
    if (!(dx >= 0 && dy >= 0 && dz >= 0)) return 0.0;
    return dx * dy + dy * dz + dz * dx;
  };
  Vec3 lo(kInfinity), hi(-kInfinity);
  for (int i = 0; i < kBvhWidth; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], nodes[0].bounds[2 * a][i]);
      hi[a] = std::max(hi[a], nodes[0].bounds[2 * a + 1][i]);
    }
  const Vec3 d = hi - lo;
  const double root = double(d.x) * d.y + double(d.y) * d.z + double(d.z) * d.x;
  if (!(root > 0.0)) return 0.0;
  double cost = 1.0;  // the root node
  for (const Bvh8Node& n : nodes)
    for (int i = 0; i < kBvhWidth; ++i) {
      if (!(n.bounds[0][i] <= n.bounds[1][i])) continue;  // empty slot
      const double a = half_area(n, i) / root;
      cost += n.info[i] == 0 ? a : a * double(n.info[i] & kLeafCountMask);
    }
  return cost;
}

bool same_nodes(const Bvh8& a, const Bvh8& b) {
  return a.nodes.size() == b.nodes.size() &&
         (a.nodes.empty() ||
          std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Bvh8Node)) == 0);
}

}  // namespace

int run_build(const BuildOptions& a) {
  std::string error;
  if (!valid_threads(a.threads, error)) return report_error(error);
  if (a.reps < 1 || a.reps > 1000) return report_error("--reps: must be between 1 and 1000");
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  const bool progress = show_progress() && !a.json;
  AccelConfig serial;
  AccelConfig parallel;
  parallel.parallel_for = thread_parallel_for(threads);
#if defined(FRAMELESS_HAVE_EMBREE)
  const bool embree = !a.no_embree;
#else
  const bool embree = false;
#endif

  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const std::string& spec : a.scenes) {
    std::unique_ptr<Scene> scene = load_scene_or_report(spec, nullptr);
    if (!scene) return 2;
    // As loaded, the primitives are in the leaf order of the load's build.
    if (a.shuffle) shuffle_primitives(scene->geometry);
    const Geometry& g = scene->geometry;
    Best ours1, oursn, emb1, embn;
    // One thread count at a time: our builds and Embree's alternate within it, so changes in
    // machine load hit both alike. Only one Embree device exists at a time (each sets TBB's
    // process-wide thread limit, and TBB applies the smallest one alive).
    for (const int nt : {1, threads}) {
      if (nt == threads && threads == 1) {
        oursn = ours1, embn = emb1;
        break;
      }
      Best& ours = nt == 1 ? ours1 : oursn;
      [[maybe_unused]] Best& emb = nt == 1 ? emb1 : embn;
      const AccelConfig& config = nt == 1 ? serial : parallel;
#if defined(FRAMELESS_HAVE_EMBREE)
      std::unique_ptr<EmbreeBench::BuildTimer> timer;
      if (embree) {
        timer = std::make_unique<EmbreeBench::BuildTimer>(nt);
        timer->build_ms(g);  // warm-up: the device starts its thread pool
      }
#endif
      Best warm_up;
      time_accel_build(g, config, warm_up);
      for (int rep = 0; rep < a.reps; ++rep) {
        if (progress)
          std::fprintf(stderr, "\r%s: %d thread(s), repetition %d/%d", spec.c_str(), nt, rep + 1,
                       a.reps);
        time_accel_build(g, config, ours);
#if defined(FRAMELESS_HAVE_EMBREE)
        if (timer) {
          double cpu = 0.0;
          const double wall = timer->build_ms(g, &cpu);
          emb.add(wall, cpu);
        }
#endif
      }
    }
    if (progress) std::fprintf(stderr, "\r%*s\r", 60, "");
    const Bvh8 tree = build_tree(g, serial);
    const bool same = same_nodes(tree, build_tree(g, parallel));
    // One thread: process CPU time (what the machine's other load does not inflate); N threads:
    // wall time.
    const double o1 = ours1.cpu, on = oursn.wall, e1 = emb1.cpu, en = embn.wall;
    nlohmann::ordered_json j;
    j["scene"] = spec;
    j["triangles"] = g.num_triangles();
    j["spheres"] = g.num_spheres();
    j["patches"] = g.num_patches();
    j["threads"] = threads;
    j["reps"] = a.reps;
    j["order"] = a.shuffle ? "shuffled" : "leaf order of the load's build";
    j["build_ms_1t"] = o1;
    j["build_ms_nt"] = on;
    j["build_ms_1t_wall"] = ours1.wall;
    j["nodes"] = tree.nodes.size();
    j["leaves"] = tree.leaves;
    j["depth"] = tree.depth;
    j["sah_cost"] = sah_cost(tree.nodes);
    j["parallel_tree_identical"] = same;
    j["clock_1t"] = "process CPU time";
    j["clock_nt"] = "wall time";
    if (embree) {
      nlohmann::ordered_json e;
      e["build_ms_1t"] = e1;
      e["build_ms_nt"] = en;
      e["build_ms_1t_wall"] = emb1.wall;
      // Ours / Embree: below 1, we are faster.
      e["ratio_1t"] = o1 / e1;
      e["ratio_nt"] = on / en;
      if (g.num_patches()) e["note"] = "Embree's scene has the triangles and spheres only";
      j["embree"] = e;
    }
    out.push_back(j);
    if (a.json) continue;
    std::printf("%s%s: %u triangles, %u spheres, %u patches; %zu nodes, depth %d, SAH cost %.3f%s\n",
                spec.c_str(), a.shuffle ? " (shuffled)" : "", g.num_triangles(), g.num_spheres(), g.num_patches(),
                tree.nodes.size(), tree.depth, j["sah_cost"].get<double>(),
                same ? "" : " (PARALLEL BUILD GAVE ANOTHER TREE)");
    std::printf("  %-28s %10s %10s\n", "build ms (best; 1T CPU time)", "1 thread",
                (std::to_string(threads) + " threads").c_str());
    std::printf("  %-28s %10.3f %10.3f\n", "ours (Accel::build)", o1, on);
    if (embree) {
      std::printf("  %-28s %10.3f %10.3f\n", "embree (rtcCommitScene)", e1, en);
      std::printf("  %-28s %10.2f %10.2f\n", "ratio ours / embree", o1 / e1, on / en);
      if (g.num_patches()) std::printf("  (Embree's scene has the triangles and spheres only)\n");
    } else if (!a.no_embree) {
      std::printf("  Embree 3 (the peer): not in this build, no ratios (tools/install-deps.sh --bench, then build again)\n");
    }
  }
  if (a.json) std::printf("%s\n", out.dump().c_str());
  return 0;
}

}  // namespace frameless::bench
