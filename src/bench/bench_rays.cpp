// `frameless bench rays`: primary- and shadow-ray throughput of the BVH, single-thread and with N
// threads, side by side with Embree (rtcIntersect1 and 8-wide packets) when it is available.
#include "bench/bench_rays.h"

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_options.h"
#include "bench/bench_report.h"
#include "core/accel/instance.h"
#include "core/accel/instance_top.h"
#include "core/base/rng.h"
#include "core/geometry/shading_frame.h"
#include "core/geometry/surface.h"
#include "core/scene/scene.h"
#include "core/shading/bsdf.h"
#include "frameless/cpu_clock.h"

#if defined(FRAMELESS_HAVE_EMBREE)
#include "bench/bench_rays_embree.h"
#endif

namespace frameless::bench {
namespace {

void set_ftz_daz() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

// Runs body(begin, end) over [0, n) in chunks on `threads` threads; returns seconds. One thread
// runs on the caller and is timed by its CPU time, which other processes on a shared machine do
// not inflate; several threads are timed by the wall clock.
double run_chunks(int threads, size_t n, const std::function<void(size_t, size_t)>& body) {
  constexpr size_t kChunk = 1024;
  std::atomic<size_t> next{0};
  auto worker = [&] {
    set_ftz_daz();
    for (;;) {
      const size_t b = next.fetch_add(kChunk);
      if (b >= n) return;
      body(b, std::min(n, b + kChunk));
    }
  };
  if (threads <= 1) {
    const double start = thread_cpu_seconds();
    worker();
    return thread_cpu_seconds() - start;
  }
  const auto start = std::chrono::steady_clock::now();
  {
    std::vector<std::thread> pool;
    for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
    for (std::thread& t : pool) t.join();
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The best and the worst of a figure's repetitions: on a shared machine one repetition may run
// far slower than the next (benchmarks.md, section 31), so the report shows the spread too.
struct Timing {
  double best = 1e30, worst = 0.0;
  void add(double s) { best = std::min(best, s), worst = std::max(worst, s); }
  double mrays(size_t rays) const { return double(rays) / best * 1e-6; }
  double mrays_worst(size_t rays) const { return double(rays) / worst * 1e-6; }
};

// The worst repetition of the four kinds of single rays, one thread, into `out` (ours or Embree's).
void put_worst(nlohmann::ordered_json& out, const Timing& primary, size_t n_primary, const Timing& shadow,
               size_t n_shadow, const Timing& bounce, size_t n_bounce, const Timing& bounce_shadow,
               size_t n_bounce_shadow) {
  out["primary_mrays_per_s_1t_worst"] = primary.mrays_worst(n_primary);
  out["shadow_mrays_per_s_1t_worst"] = shadow.mrays_worst(n_shadow);
  out["bounce_mrays_per_s_1t_worst"] = bounce.mrays_worst(n_bounce);
  out["bounce_shadow_mrays_per_s_1t_worst"] = bounce_shadow.mrays_worst(n_bounce_shadow);
}

}  // namespace

int rays_of_scene(const RaysOptions& a, const std::string& spec, nlohmann::ordered_json& j) {
  int width = 0, height = 0;
  std::string error;
  if (!parse_size(a.size, width, height, error)) return report_error(error);
  const int threads = a.threads > 0 ? a.threads : hardware_threads();
  std::unique_ptr<Scene> scene = load_scene_or_report(spec, &a.shadows);
  if (!scene) return 2;
  if (!a.camera.apply(scene->camera, error)) return report_error(error);
  const bool progress = show_progress() && !a.json;
  set_ftz_daz();

  // Build times, each the best of up to three builds as Embree's are (the load's own build is the
  // process's first: its fresh pages made it up to 1.5 times slower): serial, then parallel.
  const int builds = std::min(a.reps, 3);
  const auto best_build = [&](const AccelConfig& config) {
    AccelStats best;
    for (int b = 0; b < builds; ++b) {
      scene->accel.build(scene->geometry, config);
      if (b == 0 || scene->accel.stats().build_ms < best.build_ms) best = scene->accel.stats();
    }
    return best;
  };
  const AccelStats serial_stats = best_build(AccelConfig{});
  AccelConfig parallel_config;
  parallel_config.parallel_for = thread_parallel_for(threads);
  const double parallel_build_ms = best_build(parallel_config).build_ms;
  if (a.opaque) {  // as Embree sees the scene: no cut-outs, on flat geometry or instanced meshes
    scene->accel.set_alpha_test({});
    for (const auto& mesh : scene->geometry.instance_meshes) mesh->accel.set_alpha_test({});
  }
  const AccelStats stats = scene->accel.stats();
  const Geometry& geom = scene->geometry;

  // Primary rays through pixel centres in 4x2 blocks, block rows in scanline order: every
  // packet (ours and Embree's) is a compact block of neighbours, as in the engine.
  const CameraBasis basis = make_camera_basis(scene->camera, width, height);
  std::vector<Ray> primary;
  primary.reserve(size_t(width) * height);
  for (int by = 0; by < height; by += 2)
    for (int bx = 0; bx < width; bx += 4)
      for (int y = by; y < std::min(height, by + 2); ++y)
        for (int x = bx; x < std::min(width, bx + 4); ++x)
          primary.push_back(camera_ray(basis, float(x) + 0.5f, float(y) + 0.5f));
  std::vector<Hit> hits(primary.size());
  const Accel& accel = scene->accel;
  accel.intersect(primary[0], hits[0]);  // warm up
  run_chunks(1, primary.size(), [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) hits[i] = Hit{}, accel.intersect(primary[i], hits[i]);
  });

  // Shadow rays from every primary hit to every light (a light above the scene if it has none).
  std::vector<Vec3> lights;
  for (const Light& l : scene->lights) lights.push_back(l.position);
  if (lights.empty()) {
    Vec3 lo, hi;
    geometry_bounds(geom, lo, hi);
    lights.push_back(0.5f * (lo + hi) + Vec3(0.0f, 2.0f * (hi.y - lo.y) + 1.0f, 0.0f));
  }
  std::vector<Ray> shadow;
  size_t primary_hits = 0;
  for (size_t i = 0; i < primary.size(); ++i) {
    if (!hits[i].valid()) continue;
    ++primary_hits;
    const Vec3 p = primary[i].org + hits[i].t * primary[i].dir;
    for (const Vec3& l : lights) {
      Ray r;
      r.org = p;
      r.dir = l - p;
      // Relative offsets keep the ray off its own surface at any scene scale (bench only).
      r.tmin = 1e-4f;
      r.tmax = 1.0f - 1e-4f;
      shadow.push_back(r);
    }
  }
  // Incoherent rays, as the path tracer traces them: at each primary hit one cosine-weighted
  // diffuse bounce about the geometric normal, and from each bounce's hit a shadow ray to a light.
  std::vector<Ray> bounce, bounce_shadow;
  {
    Rng rng(7);
    for (size_t i = 0; i < primary.size(); ++i) {
      if (!hits[i].valid() || hits[i].inst != kInvalidId) continue;  // flat geometry's hits
      const SurfacePoint sp = surface_point(geom, primary[i], hits[i]);
      Ray r;
      r.org = offset_ray_origin(sp.p, sp.ng, sp.scale);
      const float u1 = rng.next_float(), u2 = rng.next_float();
      r.dir = make_shading_frame(sp.ng).to_world(sample_cosine_hemisphere(u1, u2));
      bounce.push_back(r);
    }
    for (const Ray& r : bounce) {
      Hit h;
      if (!accel.intersect(r, h) || h.inst != kInvalidId) continue;
      const SurfacePoint sp = surface_point(geom, r, h);
      Ray s;
      s.org = offset_ray_origin(sp.p, sp.ng, sp.scale);
      s.dir = lights[size_t(rng.next_u32() % lights.size())] - s.org;
      s.tmin = 0.0f;
      s.tmax = 1.0f - 1e-4f;
      bounce_shadow.push_back(s);
    }
  }
  // Work per ray, the same rays counted once: where a ray's time goes is nodes and primitives.
  struct Work {
    double nodes = 0.0, prims = 0.0;
  };
  auto work = [&](const std::vector<Ray>& rays, bool any_hit) {
    TraversalCounts c;
    for (const Ray& r : rays) {
      Hit h;
      if (any_hit) accel.occluded_counted(r, c); else accel.intersect_counted(r, h, c);
    }
    const double n = double(std::max<size_t>(rays.size(), 1));
    return Work{double(c.nodes) / n, double(c.prims) / n};
  };
  const Work work_primary = work(primary, false), work_shadow = work(shadow, true),
             work_bounce = work(bounce, false), work_bounce_shadow = work(bounce_shadow, true);
  std::vector<uint8_t> bounce_occ(bounce_shadow.size());
  std::vector<Hit> bounce_hits(bounce.size());
  Timing b1, bn, bs1, bsn;

  std::vector<uint8_t> occluded(shadow.size());
  std::vector<Hit> packet_hits(primary.size());
  std::vector<uint8_t> packet_occluded(shadow.size());
  // Packets of kPacketSize consecutive rays (a chunk is a multiple of it).
  auto trace_packets = [&](size_t b, size_t e) {
    for (size_t i = b; i < e; i += kPacketSize)
      accel.intersect_packet(primary.data() + i, int(std::min<size_t>(kPacketSize, e - i)),
                             packet_hits.data() + i);
  };
  auto occlude_packets = [&](size_t b, size_t e) {
    bool occ[kPacketSize];
    for (size_t i = b; i < e; i += kPacketSize) {
      const int m = int(std::min<size_t>(kPacketSize, e - i));
      accel.occluded_packet(shadow.data() + i, m, occ);
      for (int k = 0; k < m; ++k) packet_occluded[i + k] = occ[k];
    }
  };

  Timing p1, pn, s1, sn, pk1, pkn, sk1, skn;
#if defined(FRAMELESS_HAVE_EMBREE)
  std::unique_ptr<EmbreeBench> embree_ptr;
  const EmbreeMode embree_mode{a.embree_robust, embree_quality_of(a.embree_quality)};  // the name checked by run_rays
  // Embree's one-thread build first, while no other device lives: with the main device alive
  // (N threads), a one-thread device's build ran on all N (it measured as fast as the N-thread
  // build, half of `bench build`'s one-thread time).
  double embree_build_1t = 0.0, embree_build_nt = 0.0;
  if (!a.no_embree) {
    embree_build_1t = EmbreeBench::build_ms_with_threads(*scene, 1, builds, embree_mode);
    embree_build_nt = EmbreeBench::build_ms_with_threads(*scene, threads, builds, embree_mode);
    embree_ptr = std::make_unique<EmbreeBench>(*scene, threads, embree_mode);
  }
  std::vector<EmbreeHit> ehits(primary.size());
  std::vector<uint8_t> eocc(shadow.size());
  Timing ep1, epn, e81, e8n, es1, esn, es81, es8n, eb1, ebn, ebs1, ebsn;
  std::vector<EmbreeHit> ebhits(bounce.size());
  std::vector<uint8_t> ebocc(bounce_shadow.size());
#endif
  for (int rep = 0; rep < a.reps; ++rep) {
    if (progress) std::fprintf(stderr, "\rrepetition %d/%d", rep + 1, a.reps);
    // Interleaved: each repetition measures every variant once, so load changes hit all alike.
    for (int nt : {1, threads}) {
      Timing& tp = nt == 1 ? p1 : pn;
      Timing& ts = nt == 1 ? s1 : sn;
      tp.add(run_chunks(nt, primary.size(), [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
          Hit h;
          accel.intersect(primary[i], h);
          hits[i] = h;
        }
      }));
      ts.add(run_chunks(nt, shadow.size(), [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) occluded[i] = accel.occluded(shadow[i]);
      }));
      (nt == 1 ? b1 : bn).add(run_chunks(nt, bounce.size(), [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
          Hit h;
          accel.intersect(bounce[i], h);
          bounce_hits[i] = h;
        }
      }));
      (nt == 1 ? bs1 : bsn).add(run_chunks(nt, bounce_shadow.size(), [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) bounce_occ[i] = accel.occluded(bounce_shadow[i]);
      }));
      (nt == 1 ? pk1 : pkn).add(run_chunks(nt, primary.size(), trace_packets));
      (nt == 1 ? sk1 : skn).add(run_chunks(nt, shadow.size(), occlude_packets));
#if defined(FRAMELESS_HAVE_EMBREE)
      if (embree_ptr) {
        const EmbreeBench& embree = *embree_ptr;
        (nt == 1 ? ep1 : epn).add(run_chunks(nt, primary.size(), [&](size_t b, size_t e) {
          embree.intersect1(primary.data() + b, ehits.data() + b, e - b);
        }));
        (nt == 1 ? e81 : e8n).add(run_chunks(nt, primary.size(), [&](size_t b, size_t e) {
          embree.intersect8(primary.data() + b, ehits.data() + b, e - b);
        }));
        (nt == 1 ? es1 : esn).add(run_chunks(nt, shadow.size(), [&](size_t b, size_t e) {
          embree.occluded1(shadow.data() + b, eocc.data() + b, e - b);
        }));
        (nt == 1 ? es81 : es8n).add(run_chunks(nt, shadow.size(), [&](size_t b, size_t e) {
          embree.occluded8(shadow.data() + b, eocc.data() + b, e - b);
        }));
        (nt == 1 ? eb1 : ebn).add(run_chunks(nt, bounce.size(), [&](size_t b, size_t e) {
          embree.intersect1(bounce.data() + b, ebhits.data() + b, e - b);
        }));
        (nt == 1 ? ebs1 : ebsn).add(run_chunks(nt, bounce_shadow.size(), [&](size_t b, size_t e) {
          embree.occluded1(bounce_shadow.data() + b, ebocc.data() + b, e - b);
        }));
      }
#endif
      if (threads == 1) break;
    }
  }
  if (progress) std::fprintf(stderr, "\r%*s\r", 30, "");
  if (threads == 1) pn = p1, sn = s1, pkn = pk1, skn = sk1, bn = b1, bsn = bs1;
  size_t shadow_occluded = 0;
  for (uint8_t o : occluded) shadow_occluded += o;
  // Packets must return exactly the single rays' answers (hit, distance bits, primitive).
  size_t packet_same = 0, packet_occ_same = 0;
  for (size_t i = 0; i < primary.size(); ++i)
    packet_same += hits[i].valid() == packet_hits[i].valid() &&
                   (!hits[i].valid() ||
                    (hits[i].prim == packet_hits[i].prim && hits[i].t == packet_hits[i].t &&
                     hits[i].u == packet_hits[i].u && hits[i].v == packet_hits[i].v));
  for (size_t i = 0; i < shadow.size(); ++i) packet_occ_same += occluded[i] == packet_occluded[i];

  const size_t prims = geom.num_primitives();
  j = nlohmann::ordered_json::object();
  j["scene"] = spec;
  j["prims"] = prims;
  j["triangles"] = geom.num_triangles();
  j["spheres"] = geom.num_spheres();
  j["instances"] = geom.instances.size();
  j["represented_triangles"] = represented_triangles(geom);
  j["width"] = width;
  j["height"] = height;
  j["build_ms"] = serial_stats.build_ms;
  j["build_ms_parallel"] = parallel_build_ms;
  j["bvh_bytes"] = stats.bytes;
  j["geometry_bytes"] = stats.geometry_bytes;
  j["bytes_per_prim"] = prims ? double(stats.bytes + stats.geometry_bytes) / double(prims) : 0.0;
  for (const auto& [name, w] : {std::pair<const char*, Work>{"primary", work_primary}, {"shadow", work_shadow},
                                {"bounce", work_bounce}, {"bounce_shadow", work_bounce_shadow}})
    j["work_per_ray"][name] = {{"nodes", w.nodes}, {"prims", w.prims}};
  j["nodes"] = stats.nodes;
  j["depth"] = stats.depth;
  j["leaves"] = stats.leaves;
  j["threads"] = threads;
  j["primary_rays"] = primary.size();
  j["shadow_rays"] = shadow.size();
  j["primary_hit_fraction"] = double(primary_hits) / double(primary.size());
  j["shadow_occluded_fraction"] =
      shadow.empty() ? 0.0 : double(shadow_occluded) / double(shadow.size());
  j["primary_mrays_per_s"] = pn.mrays(primary.size());
  j["shadow_mrays_per_s"] = sn.mrays(shadow.size());
  j["primary_mrays_per_s_1t"] = p1.mrays(primary.size());
  j["shadow_mrays_per_s_1t"] = s1.mrays(shadow.size());
  j["primary_packet_mrays_per_s"] = pkn.mrays(primary.size());
  j["shadow_packet_mrays_per_s"] = skn.mrays(shadow.size());
  j["primary_packet_mrays_per_s_1t"] = pk1.mrays(primary.size());
  j["shadow_packet_mrays_per_s_1t"] = sk1.mrays(shadow.size());
  j["bounce_rays"] = bounce.size();
  j["bounce_shadow_rays"] = bounce_shadow.size();
  j["bounce_mrays_per_s_1t"] = b1.mrays(bounce.size());
  j["bounce_mrays_per_s"] = bn.mrays(bounce.size());
  j["bounce_shadow_mrays_per_s_1t"] = bs1.mrays(bounce_shadow.size());
  j["bounce_shadow_mrays_per_s"] = bsn.mrays(bounce_shadow.size());
  put_worst(j, p1, primary.size(), s1, shadow.size(), b1, bounce.size(), bs1, bounce_shadow.size());
  j["packet_size"] = kPacketSize;
  j["packet_primary_mismatches"] = primary.size() - packet_same;
  j["packet_shadow_mismatches"] = shadow.size() - packet_occ_same;
  j["reps"] = a.reps;
  j["clock_1t"] = "thread CPU time";
  j["clock_nt"] = "wall time";
#if defined(FRAMELESS_HAVE_EMBREE)
  nlohmann::ordered_json e;
  if (embree_ptr) {
    const EmbreeBench& embree = *embree_ptr;
    if (threads == 1) epn = ep1, e8n = e81, esn = es1, es8n = es81, ebn = eb1, ebsn = ebs1;
    // Agreement on hit/miss, the instance and the hit primitive (edges may legitimately differ).
    const std::shared_ptr<const InstanceTop> top = accel.instance_top();
    const auto declared = [&](const Hit& h) {  // our hit's instance as Embree numbers it
      return h.inst == kInvalidId || !top ? unsigned(RTC_INVALID_GEOMETRY_ID) : top->declared[h.inst];
    };
    size_t same_hit = 0, same_occ = 0;
    for (size_t i = 0; i < primary.size(); ++i)
      same_hit += (hits[i].valid() == ehits[i].valid()) &&
                  (!hits[i].valid() ||
                   (declared(hits[i]) == ehits[i].inst && embree.prim_id(ehits[i], geom) == hits[i].prim));
    for (size_t i = 0; i < shadow.size(); ++i) same_occ += occluded[i] == eocc[i];
    e["version"] = embree.version();
    e["robust"] = embree.robust();
    e["build_quality"] = a.embree_quality;
    e["build_ms"] = embree_build_nt;
    e["build_ms_1t"] = embree_build_1t;
    e["bytes"] = embree.bytes();
    e["primary_mrays_per_s_1t"] = ep1.mrays(primary.size());
    e["primary_packet8_mrays_per_s_1t"] = e81.mrays(primary.size());
    e["shadow_mrays_per_s_1t"] = es1.mrays(shadow.size());
    e["shadow_packet8_mrays_per_s_1t"] = es81.mrays(shadow.size());
    e["primary_mrays_per_s"] = epn.mrays(primary.size());
    e["primary_packet8_mrays_per_s"] = e8n.mrays(primary.size());
    e["shadow_mrays_per_s"] = esn.mrays(shadow.size());
    e["shadow_packet8_mrays_per_s"] = es8n.mrays(shadow.size());
    // Ratios ours / Embree (above 1: we are faster).
    e["ratio_primary_vs_intersect1_1t"] = p1.mrays(1) / ep1.mrays(1);
    e["ratio_primary_vs_packet8_1t"] = p1.mrays(1) / e81.mrays(1);
    e["ratio_shadow_vs_occluded1_1t"] = s1.mrays(1) / es1.mrays(1);
    e["ratio_shadow_vs_packet8_1t"] = s1.mrays(1) / es81.mrays(1);
    e["ratio_primary_vs_intersect1"] = pn.mrays(1) / epn.mrays(1);
    e["ratio_primary_vs_packet8"] = pn.mrays(1) / e8n.mrays(1);
    e["ratio_shadow_vs_occluded1"] = sn.mrays(1) / esn.mrays(1);
    e["ratio_shadow_vs_packet8"] = sn.mrays(1) / es8n.mrays(1);
    e["ratio_primary_packet_vs_packet8_1t"] = pk1.mrays(1) / e81.mrays(1);
    e["ratio_primary_packet_vs_intersect1_1t"] = pk1.mrays(1) / ep1.mrays(1);
    e["ratio_shadow_packet_vs_occluded1_1t"] = sk1.mrays(1) / es1.mrays(1);
    e["ratio_shadow_packet_vs_packet8_1t"] = sk1.mrays(1) / es81.mrays(1);
    e["ratio_primary_packet_vs_packet8"] = pkn.mrays(1) / e8n.mrays(1);
    e["ratio_primary_packet_vs_intersect1"] = pkn.mrays(1) / epn.mrays(1);
    e["ratio_shadow_packet_vs_occluded1"] = skn.mrays(1) / esn.mrays(1);
    e["ratio_shadow_packet_vs_packet8"] = skn.mrays(1) / es8n.mrays(1);
    if (!bounce.empty()) {
      e["ratio_bounce_vs_intersect1_1t"] = b1.mrays(1) / eb1.mrays(1);
      e["ratio_bounce_vs_intersect1"] = bn.mrays(1) / ebn.mrays(1);
    }
    if (!bounce_shadow.empty()) {
      e["ratio_bounce_shadow_vs_occluded1_1t"] = bs1.mrays(1) / ebs1.mrays(1);
      e["ratio_bounce_shadow_vs_occluded1"] = bsn.mrays(1) / ebsn.mrays(1);
    }
    put_worst(e, ep1, primary.size(), es1, shadow.size(), eb1, bounce.size(), ebs1, bounce_shadow.size());
    e["bounce_mrays_per_s_1t"] = eb1.mrays(bounce.size());
    e["bounce_shadow_mrays_per_s_1t"] = ebs1.mrays(bounce_shadow.size());
    e["primary_agreement"] = double(same_hit) / double(primary.size());
    e["shadow_agreement"] = shadow.empty() ? 1.0 : double(same_occ) / double(shadow.size());
    j["embree"] = e;
  }
#endif
  if (a.json) return 0;  // run_rays prints it
  std::printf("scene %s: %zu primitives (%u triangles, %u spheres), %dx%d, %d threads\n",
              spec.c_str(), prims, geom.num_triangles(), geom.num_spheres(), width, height,
              threads);
  if (!geom.instances.empty())
    std::printf("instances: %zu of %zu shared meshes, %llu triangles represented\n",
                geom.instances.size(), geom.instance_meshes.size(),
                (unsigned long long)represented_triangles(geom));
  std::printf(
      "BVH: build %.1f ms serial, %.1f ms parallel; %zu nodes, depth %d; "
      "%.1f bytes/prim (BVH %zu + geometry %zu)\n",
      serial_stats.build_ms, parallel_build_ms, stats.nodes, stats.depth,
      j["bytes_per_prim"].get<double>(), stats.bytes, stats.geometry_bytes);
  std::printf("work per ray (8-wide nodes entered / primitives tested): primary %.1f / %.1f, shadow %.1f / %.1f, "
              "bounce %.1f / %.1f, bounce shadow %.1f / %.1f\n",
              work_primary.nodes, work_primary.prims, work_shadow.nodes, work_shadow.prims, work_bounce.nodes,
              work_bounce.prims, work_bounce_shadow.nodes, work_bounce_shadow.prims);
  std::printf("%-28s %12s %12s\n", "Mrays/s (best, 1T: CPU time)", "1 thread",
              (std::to_string(threads) + " threads").c_str());
  auto row = [](const char* name, double one, double many) {
    std::printf("%-28s %12.2f %12.2f\n", name, one, many);
  };
  row("primary", p1.mrays(primary.size()), pn.mrays(primary.size()));
  row("shadow", s1.mrays(shadow.size()), sn.mrays(shadow.size()));
  row("primary, packets of 8", pk1.mrays(primary.size()), pkn.mrays(primary.size()));
  row("shadow, packets of 8", sk1.mrays(shadow.size()), skn.mrays(shadow.size()));
  row("diffuse bounce (incoherent)", b1.mrays(bounce.size()), bn.mrays(bounce.size()));
  row("bounce shadow (incoherent)", bs1.mrays(bounce_shadow.size()), bsn.mrays(bounce_shadow.size()));
#if defined(FRAMELESS_HAVE_EMBREE)
  if (embree_ptr) {
    const EmbreeBench& embree = *embree_ptr;
    row("embree primary intersect1", ep1.mrays(primary.size()), epn.mrays(primary.size()));
    row("embree primary intersect8", e81.mrays(primary.size()), e8n.mrays(primary.size()));
    row("embree shadow occluded1", es1.mrays(shadow.size()), esn.mrays(shadow.size()));
    row("embree shadow occluded8", es81.mrays(shadow.size()), es8n.mrays(shadow.size()));
    row("ratio primary / intersect1", p1.mrays(1) / ep1.mrays(1), pn.mrays(1) / epn.mrays(1));
    row("ratio primary / intersect8", p1.mrays(1) / e81.mrays(1), pn.mrays(1) / e8n.mrays(1));
    row("ratio shadow / occluded1", s1.mrays(1) / es1.mrays(1), sn.mrays(1) / esn.mrays(1));
    row("ratio shadow / occluded8", s1.mrays(1) / es81.mrays(1), sn.mrays(1) / es8n.mrays(1));
    row("ratio packets / intersect8", pk1.mrays(1) / e81.mrays(1), pkn.mrays(1) / e8n.mrays(1));
    row("ratio sh. packets / occl.1", sk1.mrays(1) / es1.mrays(1), skn.mrays(1) / esn.mrays(1));
    row("ratio sh. packets / occl.8", sk1.mrays(1) / es81.mrays(1), skn.mrays(1) / es8n.mrays(1));
    if (!bounce.empty())
      row("ratio bounce / intersect1", b1.mrays(1) / eb1.mrays(1), bn.mrays(1) / ebn.mrays(1));
    if (!bounce_shadow.empty())
      row("ratio bounce sh. / occl.1", bs1.mrays(1) / ebs1.mrays(1), bsn.mrays(1) / ebsn.mrays(1));
    std::printf("agreement with embree: primary %.4f, shadow %.4f (embree %s%s, %s quality, build %.1f ms on 1 "
                "thread, %.1f ms on %d)\n",
                e["primary_agreement"].get<double>(), e["shadow_agreement"].get<double>(),
                embree.version().c_str(), embree.robust() ? " robust" : "", a.embree_quality.c_str(), e["build_ms_1t"].get<double>(),
                embree_build_nt, threads);
    if (a.reps > 1)
      std::printf("spread over %d repetitions, 1 thread, worst-best Mrays/s: primary %.2f-%.2f (embree %.2f-%.2f), "
                  "bounce %.2f-%.2f (embree %.2f-%.2f)\n",
                  a.reps, p1.mrays_worst(primary.size()), p1.mrays(primary.size()), ep1.mrays_worst(primary.size()),
                  ep1.mrays(primary.size()), b1.mrays_worst(bounce.size()), b1.mrays(bounce.size()),
                  eb1.mrays_worst(bounce.size()), eb1.mrays(bounce.size()));
  }
#else
  std::printf("Embree 3 (the peer): not in this build, no ratios (tools/install-deps.sh --bench, then build again)\n");
#endif
  std::printf("packets vs single rays: %zu of %zu primary and %zu of %zu shadow results differ\n",
              primary.size() - packet_same, primary.size(), shadow.size() - packet_occ_same,
              shadow.size());
  return 0;
}

}  // namespace frameless::bench
