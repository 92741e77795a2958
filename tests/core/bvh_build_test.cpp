// The binned-SAH builders (bvh_build.h, bvh_build_spheres.h) built serially and through a real
// multi-threaded parallel_for: the same nodes byte for byte and the same primitive order (so
// images do not depend on the thread count), a sound tree (every primitive in one leaf of its
// kind, boxes that contain what is below them), and closest and any hits that agree with brute
// force.
#include "core/accel/bvh_build.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "core/accel/accel.h"
#include "core/accel/bvh_build_spheres.h"
#include "core/accel/bvh_build_split.h"
#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"
#include "core/scenes/scene_load.h"

#include "slow_build.h"

namespace frameless {
namespace {

// Brute force costs rays x primitives; sanitizers run 5-20x slower.
#if defined(FRAMELESS_SLOW_BUILD)
constexpr int kRays = 100;
#else
constexpr int kRays = 1000;
#endif

using TestRng = std::mt19937;

// A real executor: `threads` std::threads per call, dynamic order.
AccelConfig threaded(int threads) {
  AccelConfig cfg;
  cfg.parallel_for = [threads](size_t n, const std::function<void(size_t)>& body) {
    std::atomic<size_t> next{0};
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&] {
        for (size_t i; (i = next.fetch_add(1)) < n;) body(i);
      });
    for (std::thread& t : pool) t.join();
  };
  return cfg;
}

// An executor that runs everything backwards on the calling thread.
AccelConfig reversed() {
  AccelConfig cfg;
  cfg.parallel_for = [](size_t n, const std::function<void(size_t)>& body) {
    for (size_t i = n; i-- > 0;) body(i);
  };
  return cfg;
}

Vec3 uniform_vec(TestRng& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  return {d(rng), d(rng), d(rng)};
}

void add_triangle(Geometry& g, Vec3 a, Vec3 b, Vec3 c) {
  const uint32_t i = uint32_t(g.positions.size());
  g.positions.insert(g.positions.end(), {a, b, c});
  g.triangles.push_back({i, i + 1, i + 2});
  g.triangle_material.push_back(uint16_t(g.triangles.size() & 0xffff));
}

// A wavy height field of nx x nz quads (a coherent mesh, as models are) over [-1, 1]^2, plus a
// soup of random triangles, some degenerate, and a stack sharing one centroid (median fallback).
Geometry mesh(uint32_t seed, int nx, int nz, int soup) {
  TestRng rng(seed);
  Geometry g;
  auto height = [](float x, float z) { return 0.2f * std::sin(7.0f * x) * std::cos(5.0f * z); };
  for (int i = 0; i <= nx; ++i)
    for (int k = 0; k <= nz; ++k) {
      const float x = -1.0f + 2.0f * float(i) / float(nx), z = -1.0f + 2.0f * float(k) / float(nz);
      g.positions.push_back({x, height(x, z), z});
    }
  for (int i = 0; i < nx; ++i)
    for (int k = 0; k < nz; ++k) {
      const uint32_t a = uint32_t(i * (nz + 1) + k), b = a + 1, c = a + uint32_t(nz + 1),
                     d = c + 1;
      g.triangles.push_back({a, c, b});
      g.triangles.push_back({b, c, d});
      g.triangle_material.push_back(uint16_t(g.triangles.size() & 0xffff));
      g.triangle_material.push_back(uint16_t(g.triangles.size() & 0xffff));
    }
  std::uniform_real_distribution<float> size(0.005f, 0.2f);
  for (int i = 0; i < soup; ++i) {
    const Vec3 c = uniform_vec(rng, -1.0f, 1.0f);
    const float s = size(rng);
    Vec3 a = c + s * uniform_vec(rng, -1, 1), b = c + s * uniform_vec(rng, -1, 1),
         d = c + s * uniform_vec(rng, -1, 1);
    if (i % 5 == 0) d = a + 0.5f * (b - a);  // collinear: zero area
    if (i % 7 == 0) b = d = a;               // a point
    add_triangle(g, a, b, d);
  }
  for (int i = 0; i < 12; ++i)
    add_triangle(g, {0.4f, 0.5f, 0.5f}, {0.6f, 0.5f, 0.5f}, {0.5f, 0.5f + 0.01f * float(i), 0.5f});
  return g;
}

void add_spheres(Geometry& g, uint32_t seed, int n) {
  TestRng rng(seed);
  std::uniform_real_distribution<float> radius(0.001f, 0.05f);
  for (int i = 0; i < n; ++i) {
    g.spheres.push_back({uniform_vec(rng, -1.0f, 1.0f), radius(rng)});
    g.sphere_material.push_back(uint16_t(i & 0xffff));
  }
  for (int i = 0; i < 12; ++i) {  // shared centres, duplicates
    g.spheres.push_back({{-0.5f, 0.25f, 0.5f}, 0.01f * float(1 + i % 3)});
    g.sphere_material.push_back(7);
  }
}

// References as Accel::build makes them.
std::vector<PrimRef> refs_of(const Geometry& g) {
  const uint32_t nt = g.num_triangles(), ns = g.num_spheres();
  std::vector<PrimRef> refs(size_t(nt) + ns);
  for (uint32_t i = 0; i < nt; ++i) {
    const UVec3 t = g.triangles[i];
    const Vec3 &a = g.positions[t.x], &b = g.positions[t.y], &c = g.positions[t.z];
    refs[i].id = i;
    refs[i].lo = glm::min(a, glm::min(b, c));
    refs[i].hi = glm::max(a, glm::max(b, c));
  }
  for (uint32_t i = 0; i < ns; ++i) {
    const Sphere& s = g.spheres[i];
    refs[nt + i].id = nt + i;
    refs[nt + i].lo = s.center - Vec3(std::abs(s.radius));
    refs[nt + i].hi = s.center + Vec3(std::abs(s.radius));
  }
  return refs;
}

bool same_bytes(const Bvh8& a, const Bvh8& b) {
  return a.nodes.size() == b.nodes.size() && a.depth == b.depth && a.leaves == b.leaves &&
         std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Bvh8Node)) == 0;
}

bool same_order(const std::vector<PrimRef>& a, const std::vector<PrimRef>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].id != b[i].id) return false;
  return true;
}

bool slot_empty(const Bvh8Node& n, int i) { return !(n.bounds[0][i] <= n.bounds[1][i]); }

bool slot_contains(const Bvh8Node& n, int i, const Vec3& lo, const Vec3& hi) {
  for (int a = 0; a < 3; ++a)
    if (!(n.bounds[2 * a][i] <= lo[a] && hi[a] <= n.bounds[2 * a + 1][i])) return false;
  return true;
}

// Everything the traversal relies on, for a tree over refs (in their final order); returns "" or
// the first problem.
std::string check_tree(const Bvh8& bvh, const std::vector<PrimRef>& refs, uint32_t nt,
                       int max_leaf) {
  // Leaf child indices count within each kind's permuted array: map back to refs positions.
  std::vector<uint32_t> position[2];
  for (uint32_t i = 0; i < refs.size(); ++i) position[refs[i].id < nt ? 0 : 1].push_back(i);
  std::vector<int> seen(refs.size(), 0), reached(bvh.nodes.size(), 0);
  std::vector<std::pair<uint32_t, int>> stack{{0u, 1}};
  reached[0] = 1;
  int depth = 0;
  size_t leaves = 0;
  while (!stack.empty()) {
    const auto [ni, level] = stack.back();
    stack.pop_back();
    depth = std::max(depth, level);
    const Bvh8Node& node = bvh.nodes[ni];
    for (int i = 0; i < kBvhWidth; ++i) {
      if (slot_empty(node, i)) continue;
      if (node.info[i] == 0) {
        const uint32_t c = node.child[i];
        if (c >= bvh.nodes.size() || reached[c]++) return "bad or shared child node";
        for (int j = 0; j < kBvhWidth; ++j) {
          const Bvh8Node& cn = bvh.nodes[c];
          if (slot_empty(cn, j)) continue;
          const Vec3 lo(cn.bounds[0][j], cn.bounds[2][j], cn.bounds[4][j]);
          const Vec3 hi(cn.bounds[1][j], cn.bounds[3][j], cn.bounds[5][j]);
          if (!slot_contains(node, i, lo, hi)) return "child box outside its parent's slot";
        }
        stack.push_back({c, level + 1});
        continue;
      }
      const int kind = (node.info[i] & kSphereLeafBit) ? 1 : 0;
      const uint32_t count = node.info[i] & kLeafCountMask;
      if (count == 0 || int(count) > max_leaf) return "leaf size " + std::to_string(count);
      if (size_t(node.child[i]) + count > position[kind].size()) return "leaf out of range";
      ++leaves;
      for (uint32_t k = node.child[i]; k < node.child[i] + count; ++k) {
        const PrimRef& r = refs[position[kind][k]];
        ++seen[position[kind][k]];
        if ((r.id < nt ? 0 : 1) != kind) return "primitive of another kind in a leaf";
        if (!slot_contains(node, i, r.lo, r.hi)) return "primitive outside its leaf box";
      }
    }
  }
  for (int s : seen)
    if (s != 1) return "a primitive in " + std::to_string(s) + " leaves";
  for (int r : reached)
    if (r != 1) return "an unreachable node";
  if (depth != bvh.depth || leaves != bvh.leaves) return "depth or leaf count misreported";
  return "";
}

// Builds refs of g serially, with real threads and with a reversed executor; all must agree.
void expect_deterministic(const Geometry& g) {
  const uint32_t nt = g.num_triangles();
  std::vector<PrimRef> serial = refs_of(g), threads = serial, backwards = serial;
  const Bvh8 a = build_bvh8(serial, nt, {});
  const Bvh8 b = build_bvh8(threads, nt, threaded(4));
  const Bvh8 c = build_bvh8(backwards, nt, reversed());
  const int max_leaf = serial.size() < bvh_split::kCachedTreePrims ? 4 : 16;  // AccelConfig's leaf sizes
  EXPECT_EQ(check_tree(a, serial, nt, max_leaf), "");
  EXPECT_TRUE(same_bytes(a, b)) << "threaded build differs from serial";
  EXPECT_TRUE(same_bytes(a, c)) << "reversed-executor build differs from serial";
  EXPECT_TRUE(same_order(serial, threads)) << "threaded build ordered primitives differently";
  EXPECT_TRUE(same_order(serial, backwards)) << "reversed build ordered primitives differently";
}

bool brute_intersect(const Geometry& g, const Ray& ray, Hit& hit) {
  const TriangleRay tr = make_triangle_ray(ray);
  float tmax = ray.tmax;
  bool found = false;
  for (uint32_t i = 0; i < g.num_triangles(); ++i) {
    const UVec3 t = g.triangles[i];
    float th, u, v;
    if (intersect_triangle(tr, g.positions[t.x], g.positions[t.y], g.positions[t.z], ray.tmin,
                           tmax, th, u, v))
      tmax = th, hit.t = th, hit.prim = i, found = true;
  }
  for (uint32_t i = 0; i < g.num_spheres(); ++i) {
    float th;
    if (intersect_sphere(ray.org, ray.dir, g.spheres[i], ray.tmin, tmax, th))
      tmax = th, hit.t = th, hit.prim = g.num_triangles() + i, found = true;
  }
  return found;
}

// Accel built serially and with threads: identical permuted geometry, and hits that agree with
// brute force (the BVH may lose an exact tie or a near tie within rounding, never a closer hit).
void expect_queries_match(Geometry g, uint32_t seed) {
  Geometry s = g, p = g;
  Accel serial, parallel;
  serial.build(s);
  parallel.build(p, threaded(4));
  ASSERT_EQ(s.triangles, p.triangles);
  ASSERT_EQ(s.triangle_material, p.triangle_material);
  ASSERT_EQ(s.spheres.size(), p.spheres.size());
  for (size_t i = 0; i < s.spheres.size(); ++i) {
    ASSERT_EQ(s.spheres[i].center, p.spheres[i].center);
    ASSERT_EQ(s.spheres[i].radius, p.spheres[i].radius);
  }
  EXPECT_EQ(s.sphere_material, p.sphere_material);
  TestRng rng(seed);
  int hits = 0;
  for (int i = 0; i < kRays; ++i) {
    Ray ray;
    ray.org = uniform_vec(rng, -1.5f, 1.5f);
    ray.dir = uniform_vec(rng, -1.0f, 1.0f) - ray.org;  // through the scene
    Hit expect, got, got_serial;
    const bool e = brute_intersect(p, ray, expect);
    ASSERT_EQ(parallel.intersect(ray, got), e) << "ray " << i;
    ASSERT_EQ(serial.intersect(ray, got_serial), e) << "ray " << i;
    ASSERT_EQ(parallel.occluded(ray), e) << "ray " << i;
    if (!e) continue;
    ++hits;
    ASSERT_EQ(got.t, got_serial.t) << "ray " << i;
    ASSERT_EQ(got.prim, got_serial.prim) << "ray " << i;
    ASSERT_GE(got.t, expect.t) << "ray " << i;
    ASSERT_LE(got.t - expect.t, 1e-6f) << "ray " << i;
  }
  EXPECT_GT(hits, kRays / 4);
}

// The references and the leaf-order permutation as Accel::build_bvh's plain loops make them.
std::vector<PrimRef> plain_refs(const Geometry& g) {
  const uint32_t nt = g.num_triangles(), ns = g.num_spheres(), np = g.num_patches();
  std::vector<PrimRef> refs(size_t(nt) + ns + np);
  for (uint32_t i = 0; i < nt; ++i) {
    const UVec3 t = g.triangles[i];
    PrimRef& r = refs[i];
    r.id = i;
    if (t.x < g.positions.size() && t.y < g.positions.size() && t.z < g.positions.size()) {
      const Vec3 &a = g.positions[t.x], &b = g.positions[t.y], &c = g.positions[t.z];
      r.lo = glm::min(a, glm::min(b, c));
      r.hi = glm::max(a, glm::max(b, c));
    }
    if (!is_finite(r.lo) || !is_finite(r.hi)) r.lo = r.hi = Vec3(0.0f);
  }
  for (uint32_t i = 0; i < ns; ++i) {
    const Sphere& s = g.spheres[i];
    PrimRef& r = refs[nt + i];
    r.id = nt + i;
    r.lo = s.center - Vec3(std::abs(s.radius));
    r.hi = s.center + Vec3(std::abs(s.radius));
    if (!is_finite(r.lo) || !is_finite(r.hi)) r.lo = r.hi = Vec3(0.0f);
  }
  for (uint32_t i = 0; i < np; ++i) {
    PrimRef& r = refs[size_t(nt) + ns + i];
    r.id = nt + ns + i;
    r.lo = g.patches[i].lo();
    r.hi = g.patches[i].hi();
    if (!is_finite(r.lo) || !is_finite(r.hi)) r.lo = r.hi = Vec3(0.0f);
  }
  return refs;
}

template <class T>
void plain_permute(std::vector<T>& v, const PrimRef* refs, size_t n, uint32_t base,
                   uint32_t count) {
  if (v.size() != count) return;
  std::vector<T> out;
  for (size_t i = 0; i < n; ++i)
    if (refs[i].id >= base && refs[i].id - base < count) out.push_back(v[refs[i].id - base]);
  v.swap(out);
}

bool same_ref(const PrimRef& a, const PrimRef& b) {
  return a.id == b.id && a.pad == b.pad && a.lo == b.lo && a.hi == b.hi;
}

// make_prim_refs and permute_geometry (serial and threaded) against the plain loops.
void expect_refs_and_permutation_as_plain(const Geometry& g) {
  const uint32_t nt = g.num_triangles(), ns = g.num_spheres(), np = g.num_patches();
  const std::vector<PrimRef> expect = plain_refs(g);
  for (const AccelConfig& cfg : {AccelConfig{}, threaded(4)}) {
    SCOPED_TRACE(cfg.parallel_for ? "threaded" : "serial");
    PrimRefArray refs = make_prim_refs(g, cfg);
    ASSERT_EQ(refs.size(), expect.size());
    for (size_t i = 0; i < expect.size(); ++i) ASSERT_TRUE(same_ref(refs[i], expect[i])) << i;
    build_bvh8(refs.data(), refs.size(), nt, cfg, nt + ns);
    Geometry fast = g, plain = g;
    permute_geometry(fast, refs.data(), refs.size(), cfg);
    plain_permute(plain.triangles, refs.data(), refs.size(), 0, nt);
    plain_permute(plain.triangle_material, refs.data(), refs.size(), 0, nt);
    plain_permute(plain.triangle_opposite, refs.data(), refs.size(), 0, nt);
    plain_permute(plain.spheres, refs.data(), refs.size(), nt, ns);
    plain_permute(plain.sphere_material, refs.data(), refs.size(), nt, ns);
    plain_permute(plain.patch_material, refs.data(), refs.size(), nt + ns, np);
    std::vector<Vec3> patch_lo;
    for (size_t i = 0; i < refs.size(); ++i)
      if (refs[i].id >= nt + ns) patch_lo.push_back(g.patches[refs[i].id - nt - ns].lo());
    EXPECT_EQ(fast.triangles, plain.triangles);
    EXPECT_EQ(fast.triangle_material, plain.triangle_material);
    EXPECT_EQ(fast.triangle_opposite, plain.triangle_opposite);
    ASSERT_EQ(fast.spheres.size(), plain.spheres.size());
    EXPECT_EQ(std::memcmp(fast.spheres.data(), plain.spheres.data(),
                          fast.spheres.size() * sizeof(Sphere)),
              0);
    EXPECT_EQ(fast.sphere_material, plain.sphere_material);
    EXPECT_EQ(fast.patch_material, plain.patch_material);
    ASSERT_EQ(fast.patches.size(), patch_lo.size());
    for (size_t i = 0; i < patch_lo.size(); ++i) EXPECT_EQ(fast.patches[i].lo(), patch_lo[i]);
  }
}

TEST(BvhBuild, ReferencesAndPermutationAsThePlainLoops) {
  // Past the size from which they fan out; with triangles out of range or not finite, spheres
  // not finite, and a per-triangle array of another length (left alone).
  Geometry g = mesh(12, 100, 120, 2000);
  add_spheres(g, 13, 50000);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  g.triangles.push_back({0, 1, uint32_t(g.positions.size() + 5)});
  g.triangle_material.push_back(3);
  add_triangle(g, {nan, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  add_triangle(g, {kInfinity, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  g.spheres.push_back({{1.0f, 2.0f, 3.0f}, kInfinity});
  g.sphere_material.push_back(4);
  g.spheres.push_back({{1.0f, 2.0f, 3.0f}, -0.25f});
  g.sphere_material.push_back(5);
  g.triangle_opposite.assign(g.triangles.size() - 1, UVec3(7u));
  expect_refs_and_permutation_as_plain(g);
}

TEST(BvhBuild, ReferencesAndPermutationWithPatches) {
  auto room = make_builtin_scene("room");  // triangles, spheres and spline patches
  ASSERT_TRUE(room.ok()) << room.error().message;
  const Geometry& g = (*room)->geometry;
  ASSERT_GT(g.num_patches(), 0u);
  ASSERT_GT(g.num_spheres(), 0u);
  expect_refs_and_permutation_as_plain(g);
}

TEST(BvhBuild, MeshParallelBuildIsIdenticalToSerial) {
  // 200k triangles: past the parallel threshold, with chunked binning at the root.
  expect_deterministic(mesh(1, 300, 320, 8000));
}

TEST(BvhBuild, MixedParallelBuildIsIdenticalToSerial) {
  Geometry g = mesh(2, 150, 150, 5000);
  add_spheres(g, 3, 60000);
  expect_deterministic(g);
}

TEST(BvhBuild, SmallBuildsNeedNoExecutor) {
  for (int n : {1, 2, 3, 8, 9, 17, 100, 5000}) {
    SCOPED_TRACE(n);
    Geometry g;
    TestRng rng{uint32_t(n)};
    for (int i = 0; i < n; ++i) {
      const Vec3 c = uniform_vec(rng, -1.0f, 1.0f);
      add_triangle(g, c, c + Vec3(0.1f, 0.0f, 0.0f), c + Vec3(0.0f, 0.1f, 0.0f));
    }
    int calls = 0;
    AccelConfig counting;
    counting.parallel_for = [&calls](size_t m, const std::function<void(size_t)>& body) {
      ++calls;
      for (size_t i = 0; i < m; ++i) body(i);
    };
    std::vector<PrimRef> a = refs_of(g), b = a;
    const Bvh8 x = build_bvh8(a, g.num_triangles(), {});
    const Bvh8 y = build_bvh8(b, g.num_triangles(), counting);
    EXPECT_EQ(calls, 0);
    EXPECT_TRUE(same_bytes(x, y));
    EXPECT_EQ(check_tree(x, a, g.num_triangles(), 4), "");
  }
}

TEST(BvhBuild, SphereParallelBuildIsIdenticalToSerial) {
  Geometry g;
  add_spheres(g, 4, 250000);
  Geometry s = g, t = g, r = g;
  const Bvh8 a = build_bvh8_spheres(s.spheres, s.sphere_material, {});
  const Bvh8 b = build_bvh8_spheres(t.spheres, t.sphere_material, threaded(4));
  const Bvh8 c = build_bvh8_spheres(r.spheres, r.sphere_material, reversed());
  EXPECT_TRUE(same_bytes(a, b)) << "threaded build differs from serial";
  EXPECT_TRUE(same_bytes(a, c)) << "reversed-executor build differs from serial";
  ASSERT_EQ(s.spheres.size(), t.spheres.size());
  EXPECT_EQ(std::memcmp(s.spheres.data(), t.spheres.data(), s.spheres.size() * sizeof(Sphere)), 0);
  EXPECT_EQ(s.sphere_material, t.sphere_material);
  EXPECT_EQ(s.sphere_material, r.sphere_material);
}

// The query scenes are just past the size from which builds fan out through the executor.
TEST(BvhBuild, MeshQueriesMatchBruteForce) { expect_queries_match(mesh(5, 180, 200, 6000), 6); }

TEST(BvhBuild, MixedQueriesMatchBruteForce) {
  Geometry g = mesh(7, 100, 120, 3000);
  add_spheres(g, 8, 45000);
  expect_queries_match(g, 9);
}

TEST(BvhBuild, SphereQueriesMatchBruteForce) {
  Geometry g;
  add_spheres(g, 10, 70000);
  expect_queries_match(g, 11);
}

}  // namespace
}  // namespace frameless
