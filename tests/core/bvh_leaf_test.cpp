// The builders' leaf policy (bvh_build_small.h): small trees keep leaves of at most
// cached_leaf_size; trees that outgrow the caches let a range of up to max_leaf_size be one leaf
// where the exact SAH says a split would not save a node visit, and split it elsewhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/accel/accel.h"
#include "core/accel/bvh_build.h"
#include "core/accel/bvh_build_spheres.h"
#include "core/accel/bvh_build_split.h"
#include "random_geometry.h"

namespace frameless {
namespace {

using bvh_split::kCachedTreePrims;

// `clusters` clusters of `per` triangles on a grid, 10 apart: a cluster's triangles all span its
// unit cube corner to corner, so their boxes are the cube and no split of a cluster saves work.
Geometry overlapping_clusters(size_t clusters, int per) {
  Geometry g;
  const int side = int(std::ceil(std::cbrt(double(clusters))));
  for (size_t c = 0; c < clusters; ++c) {
    const Vec3 o = 10.0f * Vec3(float(c % side), float(c / side % side), float(c / side / side));
    for (int k = 0; k < per; ++k) {
      const float f = float(k) / float(per);
      add_triangle(g, o, o + Vec3(1.0f, 1.0f - f, f), o + Vec3(1.0f, 1.0f, 1.0f));
    }
  }
  return g;
}

// `clusters` clusters of `per` spheres about one centre each (radii 0.5 to 1): nested boxes.
Geometry nested_sphere_clusters(size_t clusters, int per) {
  Geometry g;
  const int side = int(std::ceil(std::cbrt(double(clusters))));
  for (size_t c = 0; c < clusters; ++c) {
    const Vec3 o = 10.0f * Vec3(float(c % side), float(c / side % side), float(c / side / side));
    for (int k = 0; k < per; ++k) add_sphere(g, o, 0.5f + 0.5f * float(k) / float(per));
  }
  return g;
}

// The most primitives any leaf of the tree holds.
int largest_leaf(const Bvh8& bvh) {
  int most = 0;
  for (const Bvh8Node& n : bvh.nodes)
    for (int i = 0; i < kBvhWidth; ++i)
      if (n.info[i] != 0) most = std::max(most, int(n.info[i] & kLeafCountMask));
  return most;
}

// The share of the tree's primitives that lie in leaves of more than four.
double share_in_large_leaves(const Bvh8& bvh) {
  size_t in_large = 0, all = 0;
  for (const Bvh8Node& n : bvh.nodes)
    for (int i = 0; i < kBvhWidth; ++i) {
      const int count = n.info[i] & kLeafCountMask;
      all += size_t(count);
      in_large += count > 4 ? size_t(count) : 0u;
    }
  return all ? double(in_large) / double(all) : 0.0;
}

Bvh8 triangle_tree(const Geometry& g, const AccelConfig& cfg) {
  std::vector<PrimRef> refs(g.num_triangles());
  for (uint32_t i = 0; i < g.num_triangles(); ++i) {
    const UVec3 t = g.triangles[i];
    const Vec3 &a = g.positions[t.x], &b = g.positions[t.y], &c = g.positions[t.z];
    refs[i].id = i;
    refs[i].lo = glm::min(a, glm::min(b, c));
    refs[i].hi = glm::max(a, glm::max(b, c));
  }
  return build_bvh8(refs, g.num_triangles(), cfg);
}

int largest_triangle_leaf(const Geometry& g, const AccelConfig& cfg = {}) {
  return largest_leaf(triangle_tree(g, cfg));
}

int largest_sphere_leaf(Geometry g, const AccelConfig& cfg = {}) {
  return largest_leaf(build_bvh8_spheres(g.spheres, g.sphere_material, cfg));
}

TEST(BvhLeaves, OverlappingPrimitivesMakeOneLeafAndFarApartOnesSplit) {
  using namespace bvh_split;
  const bool every_axis[3] = {true, true, true};
  std::vector<F4> lo, hi;
  const auto add = [&](Vec3 l, Vec3 h) { lo.push_back(f4(l)), hi.push_back(f4(h)); };
  const auto half_area = [&] {
    Box4 b;
    for (size_t i = 0; i < lo.size(); ++i) b.grow(lo[i], hi[i]);
    return b.half_area();
  };
  // Eight triangles spanning one box: their own boxes already cost what a leaf does.
  for (int k = 0; k < 8; ++k) add(Vec3(0.0f), Vec3(1.0f));
  SmallSplit found;
  EXPECT_TRUE(leaf_beats_split(lo.data(), hi.data(), 8, half_area(), kTriangleNodeCost, every_axis, found));
  EXPECT_EQ(found.axis, -1);  // decided without a split
  // Eight thin sticks across a square, four along x and four along y: their own boxes are
  // nothing, yet every split leaves at least one side the whole square, so the leaf pays.
  lo.clear(), hi.clear();
  for (int k = 0; k < 4; ++k) {
    const float at = float(k) / 3.0f;
    add(Vec3(0.0f, at, 0.0f), Vec3(1.0f, at + 1e-3f, 0.0f));
    add(Vec3(at, 0.0f, 0.0f), Vec3(at + 1e-3f, 1.0f, 0.0f));
  }
  const bool flat[3] = {true, true, false};
  EXPECT_TRUE(leaf_beats_split(lo.data(), hi.data(), 8, half_area(), kTriangleNodeCost, flat, found));
  EXPECT_GE(found.axis, 0);  // the split it weighed is kept for the builder
  // Eight tiny ones at the corners of a cube: halves are faces, a third of its area each.
  lo.clear(), hi.clear();
  for (int k = 0; k < 8; ++k) {
    const Vec3 c(float(k & 1), float(k >> 1 & 1), float(k >> 2 & 1));
    add(c - Vec3(1e-3f), c + Vec3(1e-3f));
  }
  found = SmallSplit();
  EXPECT_FALSE(leaf_beats_split(lo.data(), hi.data(), 8, half_area(), kTriangleNodeCost, every_axis, found));
  EXPECT_EQ(found.pos, 4);  // four corners a side
  // A node visit dearer than the eight tests: the leaf again.
  EXPECT_TRUE(leaf_beats_split(lo.data(), hi.data(), 8, half_area(), 8.0f, every_axis, found));
}

TEST(BvhLeaves, TreesBeyondTheCachesGrowLeavesWhereTheyPay) {
  constexpr int kPer = 12;
  const size_t big = kCachedTreePrims / kPer + 1, small = 1000;
  // Clusters no split helps: leaves of whole clusters once the tree outgrows the caches.
  EXPECT_EQ(largest_triangle_leaf(overlapping_clusters(big, kPer)), kPer);
  EXPECT_LE(largest_triangle_leaf(overlapping_clusters(small, kPer)), 4);
  EXPECT_EQ(largest_sphere_leaf(nested_sphere_clusters(big, kPer)), kPer);
  EXPECT_LE(largest_sphere_leaf(nested_sphere_clusters(small, kPer)), 4);
  // A soup of small far-apart triangles stays split, big as its tree is.
  Geometry soup;
  TestRng rng(3);
  for (size_t i = 0; i < kCachedTreePrims; ++i) {
    const Vec3 c = uniform_vec(rng, -100.0f, 100.0f);
    add_triangle(soup, c, c + Vec3(0.01f, 0.0f, 0.0f), c + Vec3(0.0f, 0.01f, 0.0f));
  }
  // (A few of its ranges of five are spread so evenly that no split of two shrinks their boxes.)
  EXPECT_LT(share_in_large_leaves(triangle_tree(soup, {})), 0.01);  // measured 0.0001
  EXPECT_GT(share_in_large_leaves(triangle_tree(overlapping_clusters(big, kPer), {})), 0.5);  // 0.70
  // The limits hold: max_leaf_size for big trees, cached_leaf_size for small ones.
  AccelConfig cfg;
  cfg.max_leaf_size = 8;
  cfg.cached_leaf_size = 2;
  EXPECT_LE(largest_triangle_leaf(overlapping_clusters(big, kPer), cfg), 8);
  EXPECT_EQ(largest_triangle_leaf(overlapping_clusters(small, kPer), cfg), 2);
  EXPECT_EQ(largest_sphere_leaf(nested_sphere_clusters(small, kPer), cfg), 2);
}

}  // namespace
}  // namespace frameless
