// The in-place sphere BVH builder (bvh_build_spheres.h) against build_bvh8 and brute force: the
// tree's structure (every sphere in exactly one leaf, leaf sizes, conservative boxes, depth
// bound), materials travelling with their spheres, identical closest hits under the traversal's
// slab test, and a layout that does not depend on the parallel executor.
#include "core/accel/bvh_build_spheres.h"
#include "core/accel/bvh_build_split.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <thread>

#include "core/accel/accel.h"
#include "core/geometry/intersect_sphere.h"

#include "slow_build.h"
#include "sphere_traversal_ref.h"

namespace frameless {
namespace {

using test_util::brute;
using test_util::traverse;

// Sanitizer builds run 5-20x slower: fewer rays there.
#if defined(FRAMELESS_SLOW_BUILD)
constexpr int kRayDivisor = 10;
#else
constexpr int kRayDivisor = 1;
#endif

using TestRng = std::mt19937;

// 16-bit fingerprint of a sphere: the material each sphere carries, so a test can tell whether
// materials were permuted with their spheres.
uint16_t fingerprint(const Sphere& s) {
  uint32_t w[4];
  std::memcpy(w, &s, sizeof w);
  uint32_t h = 2166136261u;
  for (uint32_t x : w) h = (h ^ x) * 16777619u;
  return uint16_t(h ^ (h >> 16));
}

struct SphereSet {
  std::vector<Sphere> spheres;
  std::vector<uint16_t> materials;
  void add(Vec3 c, float r) {
    spheres.push_back({c, r});
    materials.push_back(fingerprint(spheres.back()));
  }
};

Vec3 uniform_vec(TestRng& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  return {d(rng), d(rng), d(rng)};
}

SphereSet uniform_set(uint32_t seed, int n, float rmin = 0.01f, float rmax = 0.2f) {
  TestRng rng(seed);
  SphereSet s;
  std::uniform_real_distribution<float> r(rmin, rmax);
  for (int i = 0; i < n; ++i) s.add(uniform_vec(rng, -1.0f, 1.0f), r(rng));
  return s;
}

// The awkward sets: exact duplicates, shared centres, radii over ten decades, clusters far apart,
// a line with exponentially growing gaps (unbalanced SAH splits), a plane, zero and negative radii.
SphereSet awkward_set(uint32_t seed) {
  TestRng rng(seed);
  SphereSet s = uniform_set(seed, 300);
  for (int i = 0; i < 60; ++i) s.add({0.25f, -0.5f, 0.125f}, 0.1f);  // duplicates
  for (int i = 0; i < 60; ++i) s.add({-0.5f, 0.5f, 0.5f}, 0.002f * float(i + 1));  // one centre
  std::uniform_real_distribution<float> e(-6.0f, 4.0f);
  for (int i = 0; i < 80; ++i) s.add(uniform_vec(rng, -1.0f, 1.0f), std::pow(10.0f, e(rng)));
  for (int i = 0; i < 80; ++i) s.add(Vec3(1e4f) + uniform_vec(rng, -1e-3f, 1e-3f), 1e-4f);
  for (int i = 0; i < 40; ++i) s.add({std::ldexp(1.0f, i - 20), 0.0f, 0.0f}, 0.01f);
  for (int i = 0; i < 80; ++i) {
    Vec3 p = uniform_vec(rng, -1.0f, 1.0f);
    p.y = 0.75f;
    s.add(p, 0.05f);
  }
  s.add({0.1f, 0.2f, 0.3f}, 0.0f);
  s.add({0.3f, 0.2f, 0.1f}, -0.15f);  // built as |r| like build_bvh8; the loader rejects it
  std::shuffle(s.spheres.begin(), s.spheres.end(), rng);
  for (size_t i = 0; i < s.spheres.size(); ++i) s.materials[i] = fingerprint(s.spheres[i]);
  return s;
}

// Bounds of one sphere exactly as Accel::build makes them.
void sphere_box(const Sphere& s, Vec3& lo, Vec3& hi) {
  lo = s.center - Vec3(std::abs(s.radius));
  hi = s.center + Vec3(std::abs(s.radius));
  if (!is_finite(lo) || !is_finite(hi)) lo = hi = Vec3(0.0f);
}

// build_bvh8 over references made as Accel::build makes them, spheres permuted into leaf order.
Bvh8 reference_build(std::vector<Sphere>& spheres, const AccelConfig& cfg) {
  std::vector<PrimRef> refs(spheres.size());
  for (uint32_t i = 0; i < refs.size(); ++i) {
    refs[i].id = i;
    sphere_box(spheres[i], refs[i].lo, refs[i].hi);
  }
  Bvh8 bvh = build_bvh8(refs, 0, cfg);
  std::vector<Sphere> permuted;
  for (const PrimRef& r : refs) permuted.push_back(spheres[r.id]);
  spheres.swap(permuted);
  return bvh;
}

bool box_empty(const Bvh8Node& n, int i) { return !(n.bounds[0][i] <= n.bounds[1][i]); }

bool box_contains(const Bvh8Node& n, int i, const Vec3& lo, const Vec3& hi) {
  for (int a = 0; a < 3; ++a)
    if (!(n.bounds[2 * a][i] <= lo[a] && hi[a] <= n.bounds[2 * a + 1][i])) return false;
  return true;
}

// Checks everything the traversal relies on; returns "" or the first problem.
std::string check_structure(const Bvh8& bvh, const std::vector<Sphere>& spheres, int max_leaf) {
  const size_t n = spheres.size();
  if (n == 0) return bvh.nodes.empty() ? "" : "nodes for no spheres";
  if (bvh.nodes.empty()) return "no nodes";
  std::vector<int> seen(n, 0);
  std::vector<int> node_refs(bvh.nodes.size(), 0);
  node_refs[0] = 1;
  size_t leaves = 0;
  int max_level = 0;
  // (node, level)
  std::vector<std::pair<uint32_t, int>> stack{{0u, 1}};
  while (!stack.empty()) {
    const auto [ni, level] = stack.back();
    stack.pop_back();
    max_level = std::max(max_level, level);
    const Bvh8Node& node = bvh.nodes[ni];
    bool any = false;
    for (int i = 0; i < kBvhWidth; ++i) {
      if (box_empty(node, i)) {
        if (node.info[i] != 0) return "empty slot with a leaf";
        continue;
      }
      any = true;
      if (node.info[i] == 0) {
        const uint32_t c = node.child[i];
        if (c >= bvh.nodes.size()) return "child node out of range";
        if (++node_refs[c] > 1) return "node referenced twice";
        const Bvh8Node& cn = bvh.nodes[c];
        for (int j = 0; j < kBvhWidth; ++j) {
          if (box_empty(cn, j)) continue;
          const Vec3 lo(cn.bounds[0][j], cn.bounds[2][j], cn.bounds[4][j]);
          const Vec3 hi(cn.bounds[1][j], cn.bounds[3][j], cn.bounds[5][j]);
          if (!box_contains(node, i, lo, hi)) return "child box outside its parent's slot";
        }
        stack.push_back({c, level + 1});
      } else {
        if (!(node.info[i] & kSphereLeafBit) || (node.info[i] & kPatchLeafBit))
          return "leaf not marked as spheres only";
        const uint32_t count = node.info[i] & kLeafCountMask;
        if (count == 0 || int(count) > max_leaf) return "leaf size " + std::to_string(count);
        const uint32_t first = node.child[i];
        if (size_t(first) + count > n) return "leaf past the sphere array";
        ++leaves;
        for (uint32_t k = first; k < first + count; ++k) {
          ++seen[k];
          Vec3 lo, hi;
          sphere_box(spheres[k], lo, hi);
          if (!box_contains(node, i, lo, hi)) return "sphere " + std::to_string(k) + " outside its leaf box";
        }
      }
    }
    if (!any) return "node without children";
  }
  for (size_t k = 0; k < n; ++k)
    if (seen[k] != 1) return "sphere " + std::to_string(k) + " in " + std::to_string(seen[k]) + " leaves";
  for (size_t k = 0; k < node_refs.size(); ++k)
    if (node_refs[k] != 1) return "node " + std::to_string(k) + " unreachable";
  if (leaves != bvh.leaves) return "leaf count differs from Bvh8::leaves";
  if (max_level != bvh.depth) return "depth differs from Bvh8::depth";
  if (bvh.depth * (kBvhWidth - 1) + 1 > 512) return "deeper than the traversal stack allows";
  return "";
}

Ray random_ray(TestRng& rng, float extent) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Ray r;
  r.org = uniform_vec(rng, -1.5f * extent, 1.5f * extent);
  const int kind = int(unit(rng) * 4.0f);
  if (kind == 0) {  // axis-aligned: the zero-component path of the slab test
    r.dir = Vec3(0.0f);
    r.dir[int(unit(rng) * 2.999f)] = unit(rng) < 0.5f ? -1.0f : 1.0f;
  } else if (kind == 1) {  // towards a point in the set, unnormalised, bounded like shadow rays
    r.dir = uniform_vec(rng, -extent, extent) - r.org;
    r.tmax = 1.0f;
  } else {
    do r.dir = uniform_vec(rng, -1.0f, 1.0f);
    while (glm::dot(r.dir, r.dir) < 1e-4f);
    r.dir = glm::normalize(r.dir);
  }
  if (unit(rng) < 0.25f) r.tmin = unit(rng) * extent * 0.5f;
  return r;
}

// Builds both ways and checks structure, materials and closest hits on `rays` random rays.
void expect_same_hits(SphereSet set, uint32_t seed, int rays, const AccelConfig& cfg = {},
                      bool against_brute_force = true, int min_hits = -1) {
  rays = std::max(1, rays / kRayDivisor);
  const float extent = 1.0f;
  std::vector<Sphere> ref_spheres = set.spheres;
  const Bvh8 ref = reference_build(ref_spheres, cfg);
  std::vector<Sphere> before = set.spheres;
  const Bvh8 bvh = build_bvh8_spheres(set.spheres, set.materials, cfg);
  const bool cached = set.spheres.size() < bvh_split::kCachedTreePrims;  // its leaf limit
  const int max_leaf = std::clamp(cached ? cfg.cached_leaf_size : cfg.max_leaf_size, 1, kMaxLeafSize);
  ASSERT_EQ(check_structure(bvh, set.spheres, max_leaf), "");
  ASSERT_EQ(set.materials.size(), set.spheres.size());
  for (size_t i = 0; i < set.spheres.size(); ++i)
    ASSERT_EQ(set.materials[i], fingerprint(set.spheres[i])) << "material left its sphere at " << i;
  // The same spheres (a permutation): compare as sorted byte strings.
  auto sorted_bytes = [](std::vector<Sphere> v) {
    std::vector<std::array<uint32_t, 4>> w(v.size());
    std::memcpy(w.data(), v.data(), v.size() * sizeof(Sphere));
    std::sort(w.begin(), w.end());
    return w;
  };
  ASSERT_EQ(sorted_bytes(before), sorted_bytes(set.spheres));

  TestRng rng(seed);
  int hits = 0;
  for (int i = 0; i < rays; ++i) {
    const Ray ray = random_ray(rng, extent);
    Hit a, b, c;
    const bool ha = traverse(bvh, set.spheres, ray, a);
    const bool hb = traverse(ref, ref_spheres, ray, b);
    const bool hc = brute(before, ray, c);
    ASSERT_EQ(ha, hb) << "ray " << i;
    if (against_brute_force) {
      ASSERT_EQ(ha, hc) << "ray " << i;
    }
    if (!ha) continue;
    ++hits;
    ASSERT_EQ(a.t, b.t) << "ray " << i;
    if (against_brute_force) {
      ASSERT_EQ(a.t, c.t) << "ray " << i;
    }
    // Equal t on two spheres (duplicates) may pick either: the spheres must then be alike.
    ASSERT_EQ(set.spheres[a.prim].radius, ref_spheres[b.prim].radius) << "ray " << i;
    ASSERT_EQ(set.spheres[a.prim].center, ref_spheres[b.prim].center) << "ray " << i;
  }
  EXPECT_GE(hits, min_hits >= 0 ? min_hits : rays / 20) << "too few hits to compare";
}

AccelConfig reverse_parallel(int* calls = nullptr) {
  AccelConfig cfg;
  cfg.parallel_for = [calls](size_t n, const std::function<void(size_t)>& body) {
    if (calls) ++*calls;
    for (size_t i = n; i-- > 0;) body(i);  // reverse order: the layout must not depend on it
  };
  return cfg;
}

AccelConfig threaded(int threads) {
  AccelConfig cfg;
  cfg.parallel_for = [threads](size_t n, const std::function<void(size_t)>& body) {
    std::vector<std::thread> pool;
    std::atomic<size_t> next{0};
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&] {
        for (size_t i; (i = next.fetch_add(1)) < n;) body(i);
      });
    for (std::thread& t : pool) t.join();
  };
  return cfg;
}

TEST(BvhSpheres, EmptyAndSingle) {
  std::vector<Sphere> s;
  std::vector<uint16_t> m;
  EXPECT_TRUE(build_bvh8_spheres(s, m, {}).nodes.empty());
  s.push_back({Vec3(1, 2, 3), 0.5f});
  const Bvh8 b = build_bvh8_spheres(s, m, {});
  ASSERT_EQ(b.nodes.size(), 1u);
  EXPECT_EQ(b.leaves, 1u);
  EXPECT_EQ(b.depth, 1);
  EXPECT_EQ(b.nodes[0].info[0], 1 | kSphereLeafBit);
  EXPECT_EQ(b.nodes[0].child[0], 0u);
  EXPECT_EQ(b.nodes[0].bounds[0][0], 0.5f);
  EXPECT_EQ(b.nodes[0].bounds[5][0], 3.5f);
  EXPECT_TRUE(m.empty());
}

TEST(BvhSpheres, SmallSetsOfEverySize) {
  for (int n = 1; n <= 40; ++n) {
    SCOPED_TRACE(n);
    expect_same_hits(uniform_set(100 + n, n, 0.05f, 0.5f), 200 + n, 2000, {}, true, 1);
  }
}

TEST(BvhSpheres, SameHitsAsBuildBvh8OnUniformSpheres) {
  expect_same_hits(uniform_set(1, 2000), 11, 20000);
}

TEST(BvhSpheres, SameHitsOnAwkwardSets) {
  for (uint32_t seed = 2; seed < 5; ++seed) {
    SCOPED_TRACE(seed);
    expect_same_hits(awkward_set(seed), 20 + seed, 20000);
  }
}

TEST(BvhSpheres, OnlyDuplicatesAndOnlySharedCentres) {
  SphereSet dup, centre;
  for (int i = 0; i < 500; ++i) dup.add({0.1f, 0.2f, 0.3f}, 0.4f);
  for (int i = 0; i < 500; ++i) centre.add({0.1f, 0.2f, 0.3f}, 0.001f * float(i + 1));
  expect_same_hits(dup, 31, 4000);
  expect_same_hits(centre, 32, 4000);
}

TEST(BvhSpheres, OtherLeafSizesAndBins) {
  for (int leaf : {1, 2, 7, 16, 127, 500}) {
    for (int bins : {2, 5, 64, 1000}) {
      SCOPED_TRACE(std::to_string(leaf) + " per leaf, " + std::to_string(bins) + " bins");
      AccelConfig cfg;
      cfg.max_leaf_size = cfg.cached_leaf_size = leaf;  // a small set: its tree is a cached one
      cfg.sah_bins = bins;
      expect_same_hits(awkward_set(40 + uint32_t(leaf)), 41, 3000, cfg);
    }
  }
}

TEST(BvhSpheres, NonFiniteSpheresAreKeptAndNeverHit) {
  SphereSet s = uniform_set(6, 200);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  s.add({nan, 0.0f, 0.0f}, 0.1f);
  s.add({0.0f, 0.0f, 0.0f}, nan);
  s.add({kInfinity, 0.0f, 0.0f}, 0.1f);
  s.add({0.5f, 0.5f, 0.5f}, kInfinity);
  s.add({3e38f, 0.0f, 0.0f}, 3e38f);  // finite but its bounds overflow
  // Both builders give these a point box at the origin, so no ray reaches them in either tree
  // (brute force would report an infinite radius's far side at t = inf: not compared).
  expect_same_hits(s, 61, 5000, {}, false);
}

TEST(BvhSpheres, DepthStaysWithinTheStackOnAdversarialInput) {
  // Centres 2^i on a line with two bins: every SAH split peels one sphere off the far end, and
  // the peeled leaves fill the node, so binned SAH alone would be 36 levels deep (7 spheres per
  // level). Past level 32 the builder switches to medians, which halve: 34 levels.
  SphereSet s;
  for (int i = -126; i <= 126; ++i) s.add({std::ldexp(1.0f, i), 0.0f, 0.0f}, 0.0f);
  std::shuffle(s.spheres.begin(), s.spheres.end(), TestRng(5));
  for (size_t i = 0; i < s.spheres.size(); ++i) s.materials[i] = fingerprint(s.spheres[i]);
  AccelConfig cfg;
  cfg.sah_bins = 2;
  cfg.max_leaf_size = cfg.cached_leaf_size = 1;
  SphereSet copy = s;
  const Bvh8 b = build_bvh8_spheres(copy.spheres, copy.materials, cfg);
  EXPECT_EQ(check_structure(b, copy.spheres, 1), "");
  EXPECT_LE(b.depth, 34);
  // The same on a larger, less regular set with the default configuration.
  SphereSet line;
  for (int i = 0; i < 4000; ++i) {
    const float x = std::pow(1.01f, float(i));
    line.add({x, 0.0f, 0.0f}, 0.001f * x);
  }
  const Bvh8 c = build_bvh8_spheres(line.spheres, line.materials, {});
  EXPECT_EQ(check_structure(c, line.spheres, 4), "");
}

TEST(BvhSpheres, MaterialsOfAnotherSizeAreLeftAlone) {
  SphereSet s = uniform_set(7, 100);
  std::vector<uint16_t> short_mats(10, 7);
  const Bvh8 b = build_bvh8_spheres(s.spheres, short_mats, {});
  EXPECT_EQ(check_structure(b, s.spheres, 4), "");
  EXPECT_EQ(short_mats, std::vector<uint16_t>(10, 7));
}

TEST(BvhSpheres, ParallelBuildIsIdenticalToSerial) {
  // Above the parallel threshold: chunked binning at the root, parallel waves, subtree tasks.
  const SphereSet base = uniform_set(8, 300000, 0.001f, 0.01f);
  SphereSet serial = base, reversed = base, threads = base;
  int calls = 0;
  const Bvh8 a = build_bvh8_spheres(serial.spheres, serial.materials, {});
  const Bvh8 b = build_bvh8_spheres(reversed.spheres, reversed.materials, reverse_parallel(&calls));
  const Bvh8 c = build_bvh8_spheres(threads.spheres, threads.materials, threaded(3));
  EXPECT_GT(calls, 2);
  EXPECT_EQ(check_structure(a, serial.spheres, 16), "");  // a tree beyond the caches: leaves of up to 16
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  ASSERT_EQ(a.nodes.size(), c.nodes.size());
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Bvh8Node)), 0);
  EXPECT_EQ(std::memcmp(a.nodes.data(), c.nodes.data(), a.nodes.size() * sizeof(Bvh8Node)), 0);
  EXPECT_EQ(std::memcmp(serial.spheres.data(), threads.spheres.data(),
                        serial.spheres.size() * sizeof(Sphere)),
            0);
  EXPECT_EQ(serial.materials, threads.materials);
  EXPECT_EQ(serial.materials, reversed.materials);
  EXPECT_EQ(a.depth, c.depth);
  EXPECT_EQ(a.leaves, c.leaves);
}

TEST(BvhSpheres, ParallelBuildHitsLikeBuildBvh8) {
  // Large enough for the parallel path; fewer rays (brute force is the slow part).
  expect_same_hits(uniform_set(9, 100000, 0.002f, 0.02f), 91, 300, threaded(2));
}

TEST(BvhSpheres, AccelOnSphereOnlyGeometryMatchesThisTree) {
  // Whatever builder Accel::build uses for sphere-only geometry, its hits (through the real,
  // possibly AVX2, traversal) are those of this tree under the portable traversal.
  SphereSet set = awkward_set(10);
  Geometry g;
  g.spheres = set.spheres;
  g.sphere_material = set.materials;
  Accel accel;
  accel.build(g);
  const Bvh8 bvh = build_bvh8_spheres(set.spheres, set.materials, {});
  ASSERT_EQ(check_structure(bvh, set.spheres, 4), "");
  TestRng rng(101);
  int hits = 0;
  for (int i = 0; i < 20000 / kRayDivisor; ++i) {
    const Ray ray = random_ray(rng, 1.0f);
    Hit a, b;
    const bool ha = accel.intersect(ray, a);
    ASSERT_EQ(ha, traverse(bvh, set.spheres, ray, b)) << "ray " << i;
    if (!ha) continue;
    ++hits;
    ASSERT_EQ(a.t, b.t) << "ray " << i;
    ASSERT_EQ(g.spheres[a.prim].center, set.spheres[b.prim].center) << "ray " << i;
    ASSERT_EQ(g.spheres[a.prim].radius, set.spheres[b.prim].radius) << "ray " << i;
    ASSERT_EQ(g.sphere_material[a.prim], fingerprint(g.spheres[a.prim])) << "ray " << i;
  }
  EXPECT_GT(hits, 1000 / kRayDivisor);
}

}  // namespace
}  // namespace frameless
