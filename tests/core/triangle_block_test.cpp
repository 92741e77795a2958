// Triangle blocks (core/accel/triangle_block.h): which nodes get one, what it holds, and that
// every lane of the vector test answers what the scalar watertight test answers, bit for bit.
#include "core/accel/triangle_block.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <thread>
#include <utility>

#include "core/accel/accel.h"
#include "core/accel/bvh_build.h"
#include "random_geometry.h"

namespace frameless {
namespace {

#if defined(__AVX2__)

uint32_t bits(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// n triangles of size about 0.6 around random centres in [-1, 1]^3 (they overlap: rays meet several).
std::vector<LeafTriangle> overlapping_triangles(TestRng& rng, int n) {
  std::vector<LeafTriangle> tris(static_cast<size_t>(n));
  for (LeafTriangle& t : tris) {
    const Vec3 c = uniform_vec(rng, -1.0f, 1.0f);
    for (Vec3& p : t.p) p = c + 0.6f * uniform_vec(rng, -1.0f, 1.0f);
  }
  return tris;
}

// A node of eight single-triangle leaves 0..7, laid out as one block.
struct EightSingles {
  std::vector<Bvh8Node> nodes{1};
  std::vector<LeafTriangle> tris;
  std::vector<TriangleBlock> blocks;
  explicit EightSingles(std::vector<LeafTriangle> t) : tris(std::move(t)) {
    clear_node(nodes[0]);
    for (int i = 0; i < kBvhWidth; ++i) nodes[0].child[i] = uint32_t(i), nodes[0].info[i] = 1;
    blocks = lay_out_triangle_blocks(nodes, tris, AccelConfig{});
  }
};

// Compares every lane with intersect_triangle; returns the lanes that hit.
uint32_t expect_lanes_match(const EightSingles& s, const Ray& ray, float tmin, float tmax) {
  const TriangleRay tr = make_triangle_ray(ray);
  const BlockRay br(tr);
  __m256 tv = _mm256_setzero_ps(), uv = tv, vv = tv;
  uint32_t redo = 0;
  const uint32_t hits = lane_hits(block_source(s.blocks[0], br), br, 0xffu, tmin, tmax, tv, uv, vv, redo);
  alignas(32) float ts[8], us[8], vs[8];
  _mm256_store_ps(ts, tv), _mm256_store_ps(us, uv), _mm256_store_ps(vs, vv);
  EXPECT_EQ(hits & redo, 0u);
  uint32_t scalar_hits = 0;
  for (int i = 0; i < kBvhWidth; ++i) {
    const LeafTriangle& t = s.tris[size_t(i)];
    float st = 0, su = 0, sv = 0;
    const bool h = intersect_triangle(tr, t.p[0], t.p[1], t.p[2], tmin, tmax, st, su, sv);
    scalar_hits |= uint32_t(h) << i;
    if (redo >> i & 1u) continue;  // decided in double by the scalar test (its traversal does so)
    EXPECT_EQ(bool(hits >> i & 1u), h) << "lane " << i;
    if (h && (hits >> i & 1u)) {
      EXPECT_EQ(bits(ts[i]), bits(st)) << "lane " << i;
      EXPECT_EQ(bits(us[i]), bits(su)) << "lane " << i;
      EXPECT_EQ(bits(vs[i]), bits(sv)) << "lane " << i;
    }
  }
  return scalar_hits;
}

TEST(TriangleBlock, EveryLaneAnswersAsTheScalarTestOnRandomRays) {
  TestRng rng(41);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int hits = 0;
  for (int round = 0; round < 2000; ++round) {
    std::vector<LeafTriangle> tris = overlapping_triangles(rng, 8);
    if (round % 3 == 0) tris[3].p[2] = tris[3].p[0];  // degenerate: zero area
    const EightSingles s(tris);
    for (int k = 0; k < 20; ++k) {
      Ray ray;
      ray.org = uniform_vec(rng, -2.0f, 2.0f);
      ray.dir = uniform_vec(rng, -1.0f, 1.0f) - ray.org;
      if (k % 5 == 0) ray.dir = Vec3(0.0f, 0.0f, k % 2 ? 1.0f : -1.0f);  // axis-aligned
      const float tmin = k % 4 == 0 ? 0.3f * unit(rng) : 0.0f, tmax = k % 3 == 0 ? 0.8f : kInfinity;
      hits += __builtin_popcount(expect_lanes_match(s, ray, tmin, tmax));
    }
  }
  EXPECT_GT(hits, 2000);  // the comparison is not vacuous
}

// A leaf's one to four triangles transposed into lanes answer as the scalar test, lane by lane;
// the lanes past the leaf are never reported.
TEST(TriangleBlock, LeafLanesAnswerAsTheScalarTest) {
  TestRng rng(43);
  int hits = 0;
  for (int round = 0; round < 8000; ++round) {
    const std::vector<LeafTriangle> tris = overlapping_triangles(rng, 4);
    Ray ray;
    ray.org = uniform_vec(rng, -2.0f, 2.0f);
    ray.dir = uniform_vec(rng, -1.0f, 1.0f) - ray.org;
    const TriangleRay tr = make_triangle_ray(ray);
    const BlockRay br(tr);
    const uint32_t n = uint32_t(round % 4) + 1, lanes = (1u << n) - 1u;
    __m256 tv = _mm256_setzero_ps(), uv = tv, vv = tv;
    uint32_t redo = 0;
    const uint32_t got = lane_hits(leaf_source(tris.data(), n, br), br, lanes, 0.0f, kInfinity, tv, uv, vv, redo);
    alignas(32) float ts[8], us[8], vs[8];
    _mm256_store_ps(ts, tv), _mm256_store_ps(us, uv), _mm256_store_ps(vs, vv);
    ASSERT_EQ((got | redo) & ~lanes, 0u);
    for (uint32_t i = 0; i < n; ++i) {
      if (redo >> i & 1u) continue;
      float st = 0, su = 0, sv = 0;
      const bool h = intersect_triangle(tr, tris[i].p[0], tris[i].p[1], tris[i].p[2], 0.0f, kInfinity, st, su, sv);
      ASSERT_EQ(bool(got >> i & 1u), h) << "round " << round << " lane " << i;
      if (h) {
        ++hits;
        EXPECT_EQ(bits(ts[i]), bits(st));
        EXPECT_EQ(bits(us[i]), bits(su));
        EXPECT_EQ(bits(vs[i]), bits(sv));
      }
    }
  }
  EXPECT_GT(hits, 200);  // the comparison is not vacuous
}

// Rays through the shared edges and vertices of a grid of unit squares (integer coordinates):
// the single-precision edge functions are exactly 0 there, which the block leaves to the scalar
// test; every other lane still matches it.
TEST(TriangleBlock, EdgeAndVertexRaysGoToTheScalarTest) {
  std::vector<LeafTriangle> tris;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      const Vec3 a(float(x), float(y), 0), b(float(x + 1), float(y), 0), c(float(x + 1), float(y + 1), 0),
          d(float(x), float(y + 1), 0);
      tris.emplace_back(a, b, c);
      tris.emplace_back(a, c, d);
    }
  const EightSingles s(tris);
  int redo_rays = 0;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j) {
      Ray ray;
      ray.org = Vec3(0.25f * float(i), 0.25f * float(j), 1.0f);
      ray.dir = Vec3(0.0f, 0.0f, -1.0f);
      const uint32_t scalar_hits = expect_lanes_match(s, ray, 0.0f, kInfinity);
      __m256 tv = _mm256_setzero_ps(), uv = tv, vv = tv;
      uint32_t redo = 0;
      const BlockRay br(make_triangle_ray(ray));
      lane_hits(block_source(s.blocks[0], br), br, 0xffu, 0.0f, kInfinity, tv, uv, vv, redo);
      redo_rays += redo != 0;
      // Inside the grid some triangle always takes the ray (watertight), in the vector test or
      // in the scalar test it hands over.
      EXPECT_NE(scalar_hits, 0u) << i << "," << j;
    }
  EXPECT_GT(redo_rays, 20);  // the edge rays really are handed over
}

TEST(TriangleBlock, NodesWithTwoSingleTriangleLeavesGetABlock) {
  std::vector<LeafTriangle> tris(20);
  for (size_t i = 0; i < tris.size(); ++i)
    for (int k = 0; k < 3; ++k) tris[i].p[k] = Vec3(float(i), float(k), float(i + k));
  std::vector<Bvh8Node> nodes(3);
  for (Bvh8Node& n : nodes) clear_node(n);
  // Node 0: singles in slots 1 and 4, a two-triangle leaf, a child node and a sphere leaf.
  nodes[0].info[1] = 1, nodes[0].child[1] = 7;
  nodes[0].info[4] = 1, nodes[0].child[4] = 12;
  nodes[0].info[2] = 2, nodes[0].child[2] = 8;
  nodes[0].info[3] = 0, nodes[0].child[3] = 1;
  nodes[0].info[5] = kSphereLeafBit | 1, nodes[0].child[5] = 0;
  // Node 1: one single only; node 2: a single naming a triangle that does not exist.
  nodes[1].info[0] = 1, nodes[1].child[0] = 3;
  nodes[2].info[0] = 1, nodes[2].child[0] = 5;
  nodes[2].info[1] = 1, nodes[2].child[1] = 99;
  const std::vector<TriangleBlock> blocks = lay_out_triangle_blocks(nodes, tris, AccelConfig{});
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(nodes[0].singles, 0x12u);
  EXPECT_EQ(nodes[0].block, 0u);
  EXPECT_EQ(nodes[1].singles, 0u);
  EXPECT_EQ(nodes[2].singles, 0u);
  for (int row = 0; row < 9; ++row) {
    EXPECT_EQ(blocks[0].v[row][1], tris[7].p[row / 3][row % 3]);
    EXPECT_EQ(blocks[0].v[row][4], tris[12].p[row / 3][row % 3]);
    EXPECT_TRUE(std::isnan(blocks[0].v[row][0]));  // unused lanes miss every ray
  }
}

// The layout in chunks through an executor numbers the blocks as one serial walk does: the same
// node and block bytes with chunks of a few nodes on threads in any order, as with one chunk.
TEST(TriangleBlock, ChunkedLayoutIsTheSerialOne) {
  Geometry g = random_triangles(91, 4000, true);
  const uint32_t nt = g.num_triangles();
  PrimRefArray refs = make_prim_refs(g, AccelConfig{});
  const Bvh8 bvh = build_bvh8(refs.data(), refs.size(), nt, AccelConfig{}, nt);
  permute_geometry(g, refs.data(), refs.size(), AccelConfig{});
  std::vector<LeafTriangle> tris;
  lay_out_leaf_triangles(g, AccelConfig{}, tris);
  ASSERT_GT(bvh.nodes.size(), 100u);
  std::vector<Bvh8Node> serial = bvh.nodes;
  const std::vector<TriangleBlock> serial_blocks = lay_out_triangle_blocks(serial, tris, AccelConfig{});
  ASSERT_GT(serial_blocks.size(), 20u);
  AccelConfig threads;  // two threads taking chunks as they come
  threads.parallel_for = [](size_t n, const std::function<void(size_t)>& body) {
    std::atomic<size_t> next{0};
    std::thread a([&] { for (size_t i; (i = next.fetch_add(1)) < n;) body(i); });
    for (size_t i; (i = next.fetch_add(1)) < n;) body(i);
    a.join();
  };
  AccelConfig backwards;
  backwards.parallel_for = [](size_t n, const std::function<void(size_t)>& body) {
    for (size_t i = n; i-- > 0;) body(i);
  };
  for (const auto& [config, chunk] : {std::pair{threads, size_t(7)}, std::pair{backwards, size_t(13)}}) {
    std::vector<Bvh8Node> nodes = bvh.nodes;
    const std::vector<TriangleBlock> blocks = lay_out_triangle_blocks(nodes, tris, config, chunk);
    ASSERT_EQ(nodes.size(), serial.size());
    EXPECT_EQ(std::memcmp(nodes.data(), serial.data(), nodes.size() * sizeof(Bvh8Node)), 0) << "chunk " << chunk;
    ASSERT_EQ(blocks.size(), serial_blocks.size());
    EXPECT_EQ(std::memcmp(blocks.data(), serial_blocks.data(), blocks.size() * sizeof(TriangleBlock)), 0)
        << "chunk " << chunk;
  }
}

// The BVH with blocks counts them in its memory and still matches the unblocked answer of the
// same triangles walked one by one (brute force) for closest and any hit.
TEST(TriangleBlock, AccelWithBlocksMatchesBruteForce) {
  Geometry g = random_triangles(77, 64, true);
  const Geometry copy = g;
  Accel accel;
  accel.build(g);
  EXPECT_GE(accel.stats().bytes, g.num_triangles() * sizeof(LeafTriangle) + sizeof(TriangleBlock));
  TestRng rng(78);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Ray ray;
    ray.org = uniform_vec(rng, -1.5f, 1.5f);
    ray.dir = uniform_vec(rng, -1.0f, 1.0f) - ray.org;
    Hit got;
    const bool a = accel.intersect(ray, got);
    // Brute force over the permuted geometry (the build reorders triangles).
    const TriangleRay tr = make_triangle_ray(ray);
    bool e = false;
    float best = ray.tmax, bu = 0, bv = 0;
    uint32_t prim = 0;
    for (uint32_t k = 0; k < g.num_triangles(); ++k) {
      const UVec3 t = g.triangles[k];
      float th, u, v;
      if (intersect_triangle(tr, g.positions[t.x], g.positions[t.y], g.positions[t.z], ray.tmin, best, th, u, v) &&
          (!e || th < best))
        e = true, best = th, bu = u, bv = v, prim = k;
    }
    ASSERT_EQ(a, e) << i;
    ASSERT_EQ(accel.occluded(ray), e) << i;
    if (!e) continue;
    ++hits;
    ASSERT_EQ(got.t, best) << i;
    if (got.prim == prim) {
      ASSERT_EQ(got.u, bu) << i;
      ASSERT_EQ(got.v, bv) << i;
    }
  }
  EXPECT_GT(hits, 2000);
  EXPECT_EQ(copy.num_triangles(), g.num_triangles());
}

#endif  // __AVX2__

}  // namespace
}  // namespace frameless
