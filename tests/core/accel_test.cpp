// The BVH against brute force on random scenes (closest hit and any hit), permutation and memory.
#include "core/accel/accel.h"
#include "core/accel/bvh_build_split.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"
#include "random_geometry.h"

#include "slow_build.h"

namespace frameless {
namespace {

// About two million rays over the suite in Release; sanitizers run 5-20x slower.
#if defined(FRAMELESS_SLOW_BUILD)
constexpr int kRaysPerScene = 20000;
constexpr int kBudgetScale = 4;
#else
constexpr int kRaysPerScene = 400000;
constexpr int kBudgetScale = 1;
#endif

bool brute_intersect(const Geometry& g, const Ray& ray, Hit& hit) {
  const TriangleRay tr = make_triangle_ray(ray);
  float tmax = ray.tmax;
  bool found = false;
  for (uint32_t i = 0; i < g.num_triangles(); ++i) {
    const UVec3 t = g.triangles[i];
    float th, u, v;
    if (intersect_triangle(tr, g.positions[t.x], g.positions[t.y], g.positions[t.z], ray.tmin, tmax,
                           th, u, v)) {
      tmax = th, hit.t = th, hit.u = u, hit.v = v, hit.prim = i, found = true;
    }
  }
  for (uint32_t i = 0; i < g.num_spheres(); ++i) {
    float th;
    if (intersect_sphere(ray.org, ray.dir, g.spheres[i], ray.tmin, tmax, th)) {
      tmax = th, hit.t = th, hit.prim = g.num_triangles() + i, found = true;
    }
  }
  return found;
}

// Distance at which prim is hit by ray (infinity if not), to accept ties between primitives.
float hit_distance(const Geometry& g, const Ray& ray, uint32_t prim) {
  float th = kInfinity, u, v;
  if (prim < g.num_triangles()) {
    const UVec3 t = g.triangles[prim];
    intersect_triangle(make_triangle_ray(ray), g.positions[t.x], g.positions[t.y], g.positions[t.z],
                       ray.tmin, ray.tmax, th, u, v);
  } else {
    intersect_sphere(ray.org, ray.dir, g.spheres[prim - g.num_triangles()], ray.tmin, ray.tmax, th);
  }
  return th;
}

Ray random_ray(TestRng& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Ray r;
  r.org = uniform_vec(rng, -1.5f, 1.5f);
  const int kind = int(unit(rng) * 4.0f);
  if (kind == 0) {  // axis-aligned directions exercise the zero-component path of the slab test
    r.dir = Vec3(0.0f);
    r.dir[int(unit(rng) * 2.999f)] = unit(rng) < 0.5f ? -1.0f : 1.0f;
  } else if (kind == 1) {  // towards a point in the scene, unnormalised, as shadow rays are
    r.dir = uniform_vec(rng, -1.0f, 1.0f) - r.org;
    r.tmax = 1.0f;
  } else {
    do r.dir = uniform_vec(rng, -1.0f, 1.0f);
    while (glm::dot(r.dir, r.dir) < 1e-4f);
    r.dir = glm::normalize(r.dir);
  }
  if (unit(rng) < 0.25f) r.tmin = unit(rng);
  if (unit(rng) < 0.25f) r.tmax = std::min(r.tmax, r.tmin + 2.0f * unit(rng));
  return r;
}

// Runs `rays` random rays through both and reports the first disagreement.
void expect_matches_brute_force(Geometry g, uint32_t seed, int rays, const AccelConfig& cfg = {}) {
  Accel accel;
  accel.build(g, cfg);
  TestRng rng(seed);
  int hits = 0, occluded = 0, near_ties = 0;
  for (int i = 0; i < rays; ++i) {
    const Ray ray = random_ray(rng);
    Hit expect, got;
    const bool e = brute_intersect(g, ray, expect);
    const bool a = accel.intersect(ray, got);
    ASSERT_EQ(e, a) << "ray " << i;
    ASSERT_EQ(accel.occluded(ray), e) << "any-hit, ray " << i;
    if (!e) continue;
    ++hits;
    occluded += accel.occluded(ray);
    if (got.t != expect.t) {
      // A near tie: two primitives within the triangle test's rounding error (its t is accurate
      // relative to the coordinates, not to t) may be ordered differently once a box entry
      // distance culls the other one. The BVH may never find a closer hit than brute force.
      ASSERT_GT(got.t, expect.t) << "ray " << i;
      ASSERT_LE(got.t - expect.t, 1e-6f) << "ray " << i;
      ASSERT_EQ(hit_distance(g, ray, got.prim), got.t) << "ray " << i;
      ++near_ties;
      continue;
    }
    if (got.prim != expect.prim) {
      // Equal distances on two primitives: either answer is right if it really is at t.
      ASSERT_EQ(hit_distance(g, ray, got.prim), expect.t) << "ray " << i;
    } else if (got.prim < g.num_triangles()) {
      ASSERT_EQ(got.u, expect.u);
      ASSERT_EQ(got.v, expect.v);
    }
  }
  // The scenes are dense enough that a fair share of rays hit: the comparison is not vacuous.
  EXPECT_GT(hits, rays / 20);
  EXPECT_EQ(occluded, hits);
  EXPECT_LE(near_ties, rays / 10000 + 1);
}

TEST(Accel, EmptySceneHitsNothing) {
  Geometry g;
  Accel accel;
  accel.build(g);
  Ray r;
  Hit h;
  EXPECT_FALSE(accel.intersect(r, h));
  EXPECT_FALSE(accel.occluded(r));
  EXPECT_FALSE(h.valid());
}

TEST(Accel, SinglePrimitive) {
  Geometry g;
  add_sphere(g, {0, 0, 0}, 1.0f);
  Accel accel;
  accel.build(g);
  Ray r;
  r.org = {0, 0, -5};
  Hit h;
  ASSERT_TRUE(accel.intersect(r, h));
  EXPECT_FLOAT_EQ(h.t, 4.0f);
  EXPECT_EQ(h.prim, 0u);
  r.tmax = 3.0f;
  EXPECT_FALSE(accel.occluded(r));
}

// The traversal reads each triangle's vertices from the copy the build lays out in leaf order:
// a rebuild after the vertices moved must see them where they are now.
TEST(Accel, RebuildSeesMovedVertices) {
  Geometry g = random_triangles(4, 400, false);
  Accel accel;
  accel.build(g);
  for (Vec3& p : g.positions) p = Vec3(p.z, p.x + 0.25f, p.y - 0.5f);
  accel.build(g);
  TestRng rng(22);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const Ray ray = random_ray(rng);
    Hit expect, got;
    const bool e = brute_intersect(g, ray, expect);
    ASSERT_EQ(accel.intersect(ray, got), e) << "ray " << i;
    ASSERT_EQ(accel.occluded(ray), e) << "any-hit, ray " << i;
    if (!e) continue;
    ++hits;
    ASSERT_EQ(got.t, expect.t) << "ray " << i;
  }
  EXPECT_GT(hits, 1000);
}

// A triangle naming a vertex that does not exist (readers refuse them; the BVH must not trust
// that) is never hit, and its vertices are never read: a ray through its point box at the origin
// misses it (ASan would see the read past the vertices).
TEST(Accel, TriangleWithAMissingVertexIsMissed) {
  Geometry g;
  add_triangle(g, {5.0f, -1.0f, 0.0f}, {7.0f, -1.0f, 0.0f}, {6.0f, 1.0f, 0.0f});
  g.triangles.push_back({0u, 1u, 99u});
  g.triangle_material.push_back(0);
  Accel accel;
  accel.build(g);
  Ray r;
  r.org = {0.0f, 0.0f, -5.0f};
  r.dir = {0.0f, 0.0f, 1.0f};
  Hit h;
  EXPECT_FALSE(accel.intersect(r, h));
  EXPECT_FALSE(accel.occluded(r));
  r.org = {6.0f, 0.0f, -5.0f};  // the good triangle is still there
  ASSERT_TRUE(accel.intersect(r, h));
  EXPECT_FLOAT_EQ(h.t, 5.0f);
}

// Shadow rays descend into the nearest box first: along a row of clusters whose boxes all hold
// the ray, only the nearest one blocks it, so the walk tests that cluster's triangle and no
// other, whichever way along the row the ray goes (in the builder's slot order one direction
// would meet the far clusters first).
TEST(Accel, ShadowRaysTryTheNearestBoxFirst) {
  Geometry g;
  for (int c = 0; c < 8; ++c) {
    const float x = 10.0f * float(c);
    if (c == 3) {  // the blocker: one triangle across the axis
      add_triangle(g, {x, -1.0f, -1.0f}, {x, 1.0f, -1.0f}, {x, 0.0f, 1.0f});
      continue;
    }
    // A ring around the axis: its box holds the axis, none of its triangles does.
    add_triangle(g, {x, 0.2f, -1.0f}, {x, 1.0f, -1.0f}, {x, 0.6f, 1.0f});
    add_triangle(g, {x, -0.2f, -1.0f}, {x, -1.0f, -1.0f}, {x, -0.6f, 1.0f});
    add_triangle(g, {x, -1.0f, 0.2f}, {x, 1.0f, 0.2f}, {x, 0.0f, 1.0f});
    add_triangle(g, {x, -1.0f, -0.2f}, {x, 1.0f, -0.2f}, {x, 0.0f, -1.0f});
  }
  Accel accel;
  accel.build(g);
  for (const float dir : {1.0f, -1.0f}) {
    Ray r;
    r.org = {30.0f - 5.0f * dir, 0.0f, 0.0f};  // just before the blocker
    r.dir = {dir, 0.0f, 0.0f};
    r.tmax = 100.0f;
    TraversalCounts counts;
    ASSERT_TRUE(accel.occluded_counted(r, counts)) << dir;
    EXPECT_EQ(counts.prims, 1u) << "direction " << dir;
  }
}

TEST(Accel, MatchesBruteForceOnTriangles) {
  expect_matches_brute_force(random_triangles(1, 100, false), 11, kRaysPerScene);
}

TEST(Accel, MatchesBruteForceOnDegenerateTriangles) {
  expect_matches_brute_force(random_triangles(2, 100, true), 12, kRaysPerScene);
}

TEST(Accel, MatchesBruteForceOnSpheres) {
  expect_matches_brute_force(random_spheres(3, 100), 13, kRaysPerScene);
}

TEST(Accel, MatchesBruteForceOnMixedScene) {
  expect_matches_brute_force(mixed_scene(4, 100), 14, kRaysPerScene);
}

TEST(Accel, MatchesBruteForceWithOtherLeafSizesAndBins) {
  AccelConfig cfg;  // small scenes: their trees take the cached trees' leaf size
  cfg.cached_leaf_size = 1;
  cfg.sah_bins = 2;
  expect_matches_brute_force(mixed_scene(5, 100), 15, kRaysPerScene / 4, cfg);
  cfg.cached_leaf_size = 16;
  cfg.sah_bins = 64;
  expect_matches_brute_force(mixed_scene(6, 100), 16, kRaysPerScene / 4, cfg);
}

TEST(Accel, MatchesBruteForceOnDeepTree) {
  // Many small primitives: several node levels and the parallel-build fan-out.
  AccelConfig cfg;
  int calls = 0;
  cfg.parallel_for = [&calls](size_t n, const std::function<void(size_t)>& body) {
    ++calls;
    for (size_t i = n; i-- > 0;) body(i);  // reverse order: the layout must not depend on it
  };
  Geometry g = mixed_scene(7, 80000);
  expect_matches_brute_force(g, 17, kRaysPerScene / 400, cfg);
  EXPECT_GE(calls, 1);  // how many waves fan out depends on the splits
}

TEST(Accel, MatchesBruteForceOnATreeWithLargeLeaves) {
  // Enough primitives for the leaves of trees beyond the caches (bvh_build_small.h): clusters of
  // overlapping triangles and of nested spheres, which become leaves of up to 16.
  Geometry g;
  TestRng rng(18);
  const int side = 24;
  for (int c = 0; g.num_triangles() + g.num_spheres() < bvh_split::kCachedTreePrims + 1000; ++c) {
    const Vec3 o = Vec3(-1.0f) + (2.0f / float(side)) * Vec3(float(c % side), float(c / side % side), float(c / side / side % side));
    for (int k = 0; k < 9; ++k)
      add_triangle(g, o + uniform_vec(rng, 0.0f, 0.04f), o + uniform_vec(rng, 0.0f, 0.04f), o + uniform_vec(rng, 0.0f, 0.04f));
    for (int k = 0; k < 3; ++k) add_sphere(g, o + Vec3(0.02f), 0.005f * float(k + 1));
  }
  expect_matches_brute_force(g, 19, kRaysPerScene / 800);
}

TEST(Accel, ParallelAndSerialBuildsAreIdentical) {
  Geometry a = mixed_scene(8, 70000), b = a;
  AccelConfig cfg;
  cfg.parallel_for = [](size_t n, const std::function<void(size_t)>& body) {
    for (size_t i = n; i-- > 0;) body(i);
  };
  Accel serial, parallel;
  serial.build(a);
  parallel.build(b, cfg);
  EXPECT_EQ(serial.stats().nodes, parallel.stats().nodes);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.spheres.size(), b.spheres.size());
  TestRng rng(18);
  for (int i = 0; i < 2000; ++i) {
    const Ray r = random_ray(rng);
    Hit ha, hb;
    ASSERT_EQ(serial.intersect(r, ha), parallel.intersect(r, hb));
    ASSERT_EQ(ha.t, hb.t);
    ASSERT_EQ(ha.prim, hb.prim);
  }
}

TEST(Accel, PermutationKeepsMaterialsWithTheirPrimitives) {
  Geometry g = mixed_scene(9, 2000);
  const Geometry original = g;
  Accel accel;
  accel.build(g);
  ASSERT_EQ(g.num_triangles(), original.num_triangles());
  ASSERT_EQ(g.num_spheres(), original.num_spheres());
  // Material ids were set to the original index: each primitive must still carry its own.
  std::vector<int> seen(g.num_primitives(), 0);
  for (uint32_t i = 0; i < g.num_triangles(); ++i) {
    const uint16_t m = g.triangle_material[i];
    EXPECT_EQ(g.triangles[i], original.triangles[m]);
    ++seen[m];
  }
  for (uint32_t i = 0; i < g.num_spheres(); ++i) {
    const uint16_t m = g.sphere_material[i];
    EXPECT_EQ(g.spheres[i].center, original.spheres[m].center);
    ++seen[g.num_triangles() + m];
  }
  for (int s : seen) ASSERT_EQ(s, 1);
}

TEST(Accel, MemoryBudget) {
  // At most 48 bytes per sphere and 120 per triangle for BVH plus geometry (a triangle's
  // vertices are kept a second time in leaf order, 36 bytes, and a third in its node's triangle
  // block when it is a leaf of its own, for the rays' sake: 106 here; Embree's triangle leaves
  // take about 72 bytes a triangle with its tree, beside the application's own arrays).
  const int n = 200000 / kBudgetScale;
  Geometry s = random_spheres(10, n);
  Accel a;
  a.build(s);
  EXPECT_LE(a.stats().bytes + a.stats().geometry_bytes, size_t(48) * n);
  EXPECT_GT(a.stats().bytes, 0u);
  // A closed grid mesh: vertices shared by about two triangles each, as in real meshes.
  Geometry m;
  const int k = 300 / kBudgetScale;
  for (int y = 0; y <= k; ++y)
    for (int x = 0; x <= k; ++x)
      m.positions.push_back({float(x), float(y), std::sin(float(x * y) * 0.01f)});
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < k; ++x) {
      const uint32_t i = uint32_t(y * (k + 1) + x);
      m.triangles.push_back({i, i + 1, i + uint32_t(k) + 1});
      m.triangles.push_back({i + 1, i + uint32_t(k) + 2, i + uint32_t(k) + 1});
      m.triangle_material.insert(m.triangle_material.end(), {0, 0});
    }
  Accel b;
  b.build(m);
  EXPECT_LE(b.stats().bytes + b.stats().geometry_bytes, size_t(120) * m.num_triangles());
}

}  // namespace
}  // namespace frameless
