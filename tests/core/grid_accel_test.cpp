// The hybrid grid against brute force and the BVH (closest hit, any hit), its cell BVHs,
// traversal counters and robustness cases (its cone query: grid_cone_test.cpp).
#include "core/accel/grid_accel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/geometry/bezier.h"
#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"

#include "grid_test_util.h"

namespace frameless {
namespace {

using test_util::add_sphere;
using test_util::add_triangle;
using test_util::append;
using test_util::kRays;
using test_util::mixed_scene;
using test_util::random_spheres;
using test_util::random_triangles;
using test_util::TestRng;
using test_util::stadium;
using test_util::uniform_vec;

bool brute_intersect(const Geometry& g, const Ray& ray, Hit& hit) {
  const TriangleRay tr = make_triangle_ray(ray);
  float tmax = ray.tmax;
  bool found = false;
  for (uint32_t i = 0; i < g.num_triangles(); ++i) {
    const UVec3 t = g.triangles[i];
    float th, u, v;
    if (intersect_triangle(tr, g.positions[t.x], g.positions[t.y], g.positions[t.z], ray.tmin, tmax,
                           th, u, v))
      tmax = th, hit.t = th, hit.u = u, hit.v = v, hit.prim = i, found = true;
  }
  for (uint32_t i = 0; i < g.num_spheres(); ++i) {
    float th;
    if (intersect_sphere(ray.org, ray.dir, g.spheres[i], ray.tmin, tmax, th))
      tmax = th, hit.t = th, hit.u = hit.v = 0.0f, hit.prim = g.num_triangles() + i, found = true;
  }
  return found;
}

// Distance at which prim is hit by ray (infinity if not), to accept exact ties.
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

Ray random_ray(TestRng& rng, float spread = 1.5f) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Ray r;
  r.org = uniform_vec(rng, -spread, spread);
  const int kind = int(unit(rng) * 4.0f);
  if (kind == 0) {  // axis-parallel: zero direction components
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

struct Tally {
  int hits = 0, near_ties = 0;
};

// Two hits a near tie apart: the triangle test accepts t before its final rounding, so of two
// primitives within an ulp the winner can depend on the order they are tested in.
bool near_tie(const Geometry& g, const Ray& ray, const Hit& a, const Hit& b) {
  return std::abs(a.t - b.t) <= 1e-6f * std::max(1.0f, b.t) &&
         hit_distance(g, ray, a.prim) == a.t && hit_distance(g, ray, b.prim) == b.t;
}

// One ray through brute force, the grid and the BVH. The grid must equal brute force (prim, t,
// u, v) except for exact ties and rare near ties; so must the BVH, up to the same.
void check_ray(const Geometry& g, const GridAccel& grid, const Accel* accel, const Ray& ray,
               Tally& tally) {
  Hit expect, got;
  const bool e = brute_intersect(g, ray, expect);
  ASSERT_EQ(grid.intersect(ray, got), e);
  ASSERT_EQ(grid.occluded(ray), e);
  if (accel) {
    ASSERT_EQ(accel->occluded(ray), e);
  }
  if (!e) return;
  ++tally.hits;
  if (got.t != expect.t) {
    ASSERT_TRUE(near_tie(g, ray, got, expect)) << got.t << " vs " << expect.t;
    ++tally.near_ties;
  } else if (got.prim != expect.prim) {
    ASSERT_EQ(hit_distance(g, ray, got.prim), expect.t);  // exact tie: either is right
  } else if (got.prim < g.num_triangles()) {
    ASSERT_EQ(got.u, expect.u);
    ASSERT_EQ(got.v, expect.v);
  }
  if (!accel) return;
  Hit bvh;
  ASSERT_TRUE(accel->intersect(ray, bvh));
  if (bvh.t != got.t) {
    ASSERT_TRUE(near_tie(g, ray, bvh, got)) << bvh.t << " vs " << got.t;
    ++tally.near_ties;
  } else if (bvh.prim != got.prim) {
    ASSERT_EQ(hit_distance(g, ray, bvh.prim), got.t);
  }
}

// Random rays through the grid (built after the BVH, which permutes g, so ids agree).
void expect_same_hits(Geometry g, uint32_t seed, int rays, const GridConfig& cfg = {},
                      float spread = 1.5f) {
  Accel accel;
  accel.build(g);
  GridAccel grid;
  grid.build(g, cfg);
  TestRng rng(seed);
  Tally tally;
  for (int i = 0; i < rays; ++i) {
    SCOPED_TRACE(::testing::Message() << "ray " << i);
    check_ray(g, grid, &accel, random_ray(rng, spread), tally);
    if (::testing::Test::HasFatalFailure()) return;
  }
  // Dense enough that a fair share of rays hit: the comparison is not vacuous.
  EXPECT_GT(tally.hits, rays / 20);
  EXPECT_LE(tally.near_ties, rays / 10000 + 1);
}

TEST(GridAccel, EmptyGeometryHitsNothing) {
  Geometry g;
  GridAccel grid;
  grid.build(g);
  Ray r;
  Hit h;
  EXPECT_FALSE(grid.intersect(r, h));
  EXPECT_FALSE(grid.occluded(r));
  EXPECT_FALSE(h.valid());
  EXPECT_EQ(grid.stats().cells, 0u);
  // Only unusable primitives: nothing is built either.
  add_sphere(g, {0, 0, 0}, kInfinity);
  add_triangle(g, {0, 0, 0}, {1, 0, 0}, {0, std::nanf(""), 0});
  grid.build(g);
  EXPECT_FALSE(grid.intersect(r, h));
  EXPECT_EQ(grid.stats().refs, 0u);
}

TEST(GridAccel, SinglePrimitives) {
  Geometry g;
  add_sphere(g, {0, 0, 0}, 1.0f);
  GridAccel grid;
  grid.build(g);
  Ray r;
  r.org = {0, 0, -5};
  Hit h;
  ASSERT_TRUE(grid.intersect(r, h));
  EXPECT_FLOAT_EQ(h.t, 4.0f);
  EXPECT_EQ(h.prim, 0u);
  r.tmax = 3.0f;
  EXPECT_FALSE(grid.occluded(r));
  // One huge triangle as the whole scene, rays from everywhere.
  Geometry t;
  add_triangle(t, {-1e4f, -1e4f, 3}, {1e4f, -1e4f, 3}, {0, 1e4f, 3});
  Tally tally;
  grid.build(t);
  TestRng rng(1);
  for (int i = 0; i < 2000; ++i) check_ray(t, grid, nullptr, random_ray(rng, 10.0f), tally);
  EXPECT_GT(tally.hits, 100);
}

TEST(GridAccel, MatchesOnTriangles) {
  expect_same_hits(random_triangles(1, 200, false), 11, kRays);
}

TEST(GridAccel, MatchesOnDegenerateTriangles) {
  expect_same_hits(random_triangles(2, 200, true), 12, kRays);
}

TEST(GridAccel, MatchesOnSpheres) { expect_same_hits(random_spheres(3, 200), 13, kRays); }

TEST(GridAccel, MatchesOnMixedScene) { expect_same_hits(mixed_scene(4, 200), 14, kRays); }

TEST(GridAccel, MatchesWithOtherResolutionsAndThresholds) {
  GridConfig cfg;
  cfg.bvh_threshold = 0;  // every non-empty cell is a BVH
  expect_same_hits(mixed_scene(5, 300), 15, kRays / 4, cfg);
  cfg.bvh_threshold = 1 << 30;  // lists only
  cfg.density = 20.0f;
  expect_same_hits(mixed_scene(6, 300), 16, kRays / 4, cfg);
  cfg.density = 0.01f;  // one or a few cells
  cfg.bvh_threshold = 3;
  expect_same_hits(mixed_scene(7, 300), 17, kRays / 4, cfg);
  cfg = {};
  cfg.max_resolution = 7;
  cfg.max_cells = 100;
  expect_same_hits(mixed_scene(8, 300), 18, kRays / 4, cfg);
}

TEST(GridAccel, DenseClusterUsesCellBvhs) {
  const Geometry g = stadium(9, 4000);
  GridAccel grid;
  grid.build(g);
  EXPECT_GT(grid.stats().cell_bvhs, 0u);
  expect_same_hits(g, 19, kRays / 10);
  // Rays aimed into the cluster itself.
  Accel accel;
  Geometry h = g;
  accel.build(h);
  grid.build(h);
  TestRng rng(20);
  Tally tally;
  for (int i = 0; i < kRays / 20; ++i) {
    Ray r;
    r.org = uniform_vec(rng, -1.5f, 1.5f);
    r.dir = glm::normalize(uniform_vec(rng, 0.2f, 0.3f) - r.org);
    check_ray(h, grid, &accel, r, tally);
    ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "ray " << i;
  }
  EXPECT_GT(tally.hits, kRays / 40);
  EXPECT_LE(tally.near_ties, kRays / 20000 + 1);
}

TEST(GridAccel, AxisParallelRaysAndRaysStartingInside) {
  Geometry g = mixed_scene(10, 200);
  GridAccel grid;
  grid.build(g);
  TestRng rng(21);
  Tally tally;
  std::uniform_int_distribution<int> axis(0, 2);
  for (int i = 0; i < kRays / 4; ++i) {
    Ray r;
    // Inside the grid; a quarter exactly on planes every primitive and cell boundary may share.
    r.org = uniform_vec(rng, -0.9f, 0.9f);
    if (i % 4 == 0) r.org[axis(rng)] = i % 8 == 0 ? 0.0f : 0.5f;
    r.dir = Vec3(0.0f);
    r.dir[axis(rng)] = i % 2 ? 1.0f : -1.0f;
    if (i % 3 == 0) r.dir[axis(rng)] = 0.5f;  // two non-zero components, or a longer axis
    check_ray(g, grid, nullptr, r, tally);
    ASSERT_FALSE(::testing::Test::HasFatalFailure()) << "ray " << i;
  }
  EXPECT_GT(tally.hits, kRays / 20);
  EXPECT_LE(tally.near_ties, kRays / 40000 + 1);
  // Degenerate rays hit nothing and do not hang.
  Ray zero;
  zero.dir = Vec3(0.0f);
  Hit h;
  EXPECT_FALSE(grid.intersect(zero, h));
  Ray nan;
  nan.dir = {std::nanf(""), 0.0f, 1.0f};
  EXPECT_FALSE(grid.intersect(nan, h));
  EXPECT_FALSE(grid.occluded(nan));
}

TEST(GridAccel, FlatSceneAndDistantOrigins) {
  // All triangles in one plane: one cell thick, the density goes to the other two axes.
  Geometry g;
  TestRng rng(22);
  for (int i = 0; i < 500; ++i) {
    const Vec3 c = uniform_vec(rng, -1, 1) * Vec3(1, 1, 0);
    add_triangle(g, c, c + Vec3(0.1f, 0, 0), c + Vec3(0, 0.1f, 0));
  }
  GridAccel grid;
  grid.build(g);
  EXPECT_EQ(grid.stats().res[2], 1);
  EXPECT_GT(grid.stats().res[0], 10);
  EXPECT_LE(grid.stats().cells, size_t(4 * 500));  // the density holds in the plane
  Tally tally;
  for (int i = 0; i < kRays / 4; ++i) check_ray(g, grid, nullptr, random_ray(rng), tally);
  EXPECT_GT(tally.hits, kRays / 100);
  EXPECT_LE(tally.near_ties, kRays / 40000 + 1);
  // Origins ten scene radii away still find exactly the same hits.
  expect_same_hits(mixed_scene(23, 300), 24, kRays / 4, {}, 10.0f);
}

TEST(GridAccel, IgnoresNonFinitePrimitives) {
  Geometry g = mixed_scene(25, 200);
  Geometry finite = g;
  add_sphere(g, {0, 0, 0}, kInfinity);
  add_sphere(g, {std::nanf(""), 0, 0}, 1.0f);
  add_triangle(g, {0, 0, 0}, {1, 0, 0}, {0, kInfinity, 0});
  g.triangles.push_back({0, 1, 1u << 30});  // vertex index out of range
  g.triangle_material.push_back(0);
  GridAccel grid, ref;
  grid.build(g);
  ref.build(finite);
  EXPECT_EQ(grid.stats().refs, ref.stats().refs);
  TestRng rng(26);
  for (int i = 0; i < kRays / 10; ++i) {
    const Ray r = random_ray(rng);
    Hit a, b;
    ASSERT_EQ(grid.intersect(r, a), ref.intersect(r, b)) << "ray " << i;
    // Ids of spheres moved by the added triangles.
    const uint32_t shift = g.num_triangles() - finite.num_triangles();
    ASSERT_EQ(a.t, b.t);
    if (b.valid()) {
      ASSERT_EQ(a.prim, b.prim < finite.num_triangles() ? b.prim : b.prim + shift);
    }
  }
}

TEST(GridAccel, MatchesWithSplinePatches) {
  Geometry g = mixed_scene(34, 100);
  TestRng rng(35);
  for (int i = 0; i < 12; ++i) {
    BezierPatch p;
    const Vec3 c = uniform_vec(rng, -0.8f, 0.8f);
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k)
        p.p[4 * r + k] = c + Vec3(0.15f * float(k) - 0.225f, 0.15f * float(r) - 0.225f, 0.0f) +
                         0.1f * uniform_vec(rng, -1, 1);
    g.patches.emplace_back(p, 3);
    g.patch_material.push_back(0);
  }
  Accel accel;
  accel.build(g);
  GridAccel grid;
  grid.build(g);
  int patch_hits = 0, exact = 0, hits = 0;
  for (int i = 0; i < kRays / 10; ++i) {
    const Ray r = random_ray(rng);
    Hit a, b;
    const bool e = accel.intersect(r, a);
    ASSERT_EQ(grid.intersect(r, b), e) << "ray " << i;
    ASSERT_EQ(grid.occluded(r), accel.occluded(r)) << "ray " << i;
    if (!e) continue;
    ++hits;
    patch_hits += b.prim >= g.first_patch();
    // Broyden's roots are accurate to a tolerance, not to the bit, and depend on the interval.
    ASSERT_NEAR(a.t, b.t, 1e-5f * a.t) << "ray " << i;
    exact += a.t == b.t && a.prim == b.prim;
  }
  EXPECT_GT(patch_hits, kRays / 500);
  EXPECT_GE(exact, hits - hits / 100);
}

TEST(GridAccel, CountsAreDeterministic) {
  Geometry g = stadium(27, 2000);
  append(g, random_spheres(28, 300, 0.05f));
  GridAccel grid;
  grid.build(g);
  auto run = [&](TraversalCounts& c) {
    TestRng rng(29);
    for (int i = 0; i < 5000; ++i) {
      const Ray r = random_ray(rng);
      Hit h;
      grid.intersect(r, h, &c);
      grid.occluded(r, &c);
    }
  };
  TraversalCounts a, b;
  run(a);
  run(b);
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(a.prims, b.prims);
  EXPECT_GT(a.nodes, 5000u);
  EXPECT_GT(a.prims, 5000u);
  // A grid of lists only does different work for the same answers.
  GridConfig lists;
  lists.bvh_threshold = 1 << 30;
  grid.build(g, lists);
  TraversalCounts c;
  run(c);
  EXPECT_NE(c.prims, a.prims);
}

TEST(GridAccel, StatsAndMemory) {
  const int n = 20000;
  Geometry g = random_spheres(30, n, 0.01f);
  GridAccel grid;
  grid.build(g);
  const GridStats& s = grid.stats();
  EXPECT_EQ(s.cells, size_t(s.res[0]) * s.res[1] * s.res[2]);
  EXPECT_GE(s.cells, size_t(n));  // about density (2) cells per primitive
  EXPECT_LE(s.cells, size_t(4 * n));
  EXPECT_GE(s.refs, size_t(n));
  EXPECT_LE(s.nonempty, s.cells);
  // Offsets, occupancy bits, ids with one root slot per cell BVH, then whole BVH nodes.
  const size_t csr =
      (s.cells + 1 + s.refs + s.cell_bvhs) * sizeof(uint32_t) + (s.cells + 63) / 64 * 8;
  ASSERT_GE(s.bytes, csr);
  EXPECT_EQ((s.bytes - csr) % sizeof(GridAccel::Node), 0u);
  EXPECT_LE(s.bytes, size_t(32) * n);  // small spheres: offsets plus ids, ~12-20 bytes each
}

}  // namespace
}  // namespace frameless
