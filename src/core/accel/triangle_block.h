// A node's single-triangle leaves kept side by side (eight lanes of SoA vertices), so a ray tests
// all it enters in one AVX2 pass of the watertight test instead of visiting each leaf in turn
// (the leaf-heavy bottom of the tree is where a ray spends its triangle tests). Any thread.
#pragma once
#include <cstdint>
#include <vector>

#include "core/accel/accel_types.h"
#include "core/accel/bvh_node.h"
#include "core/accel/watertight_lanes.h"
#include "core/geometry/intersect_triangle.h"

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace frameless {

// Lane j holds the triangle of the node's slot j (rows: vertex k's axis a at 3 k + a); unused
// lanes hold NaN corners, which every test misses.
struct alignas(32) TriangleBlock {
  float v[9][kBvhWidth];
};
static_assert(sizeof(TriangleBlock) == 288);

// Whether single rays test triangles in lanes (blocks, and leaves of two or more triangles);
// FRAMELESS_TRIANGLE_BLOCKS=0 in the environment says no: every triangle is tested on its own
// (a clean A/B in one binary, as bench rays does).
bool triangle_lanes_wanted();

// Nodes with at least this many single-triangle leaves get a block.
inline constexpr int kMinBlockSingles = 2;

// Gives every node with at least kMinBlockSingles single-triangle leaves a block (its `singles`
// and `block` set, the rest cleared) and returns the blocks; triangles from `leaf_tris` (leaf order).
std::vector<TriangleBlock> lay_out_triangle_blocks(std::vector<Bvh8Node>& nodes, const std::vector<LeafTriangle>& leaf_tris,
                                                   const AccelConfig& config);

// Asks for a block's five cache lines.
inline void prefetch_block(const TriangleBlock* b) {
  const char* a = reinterpret_cast<const char*>(b);
  for (int line = 0; line < 5; ++line) __builtin_prefetch(a + 64 * line);
  __builtin_prefetch(a + sizeof(TriangleBlock) - 1);
}

#if defined(__AVX2__)
// One ray's watertight-test constants, broadcast for the lanes.
struct BlockRay {
  __m256 ox, oy, oz, neg_sx, neg_sy, sz;
  int kx, ky, kz;
  explicit BlockRay(const TriangleRay& r)
      : ox(_mm256_set1_ps(r.ox)), oy(_mm256_set1_ps(r.oy)), oz(_mm256_set1_ps(r.oz)),
        neg_sx(_mm256_set1_ps(-r.sx)), neg_sy(_mm256_set1_ps(-r.sy)), sz(_mm256_set1_ps(r.sz)),
        kx(r.kx), ky(r.ky), kz(r.kz) {}
};

// The watertight test for the lanes in `lanes` (watertight_lanes.h): returns the lanes that
// hit within [tmin, tmax] with t, b1, b2 set, and in `redo` the lanes exactly on an edge in
// single precision, for the scalar test.
inline uint32_t block_hits(const TriangleBlock& b, const BlockRay& r, uint32_t lanes, float tmin,
                           float tmax, __m256& t, __m256& b1, __m256& b2, uint32_t& redo) {
  // Vertex k's coordinate on `axis` relative to the origin's `o`.
  const auto at = [&](int k, int axis, __m256 o) { return _mm256_sub_ps(_mm256_load_ps(b.v[3 * k + axis]), o); };
  const LaneTriangle q{{at(0, r.kx, r.ox), at(0, r.ky, r.oy), at(0, r.kz, r.oz)},
                       {at(1, r.kx, r.ox), at(1, r.ky, r.oy), at(1, r.kz, r.oz)},
                       {at(2, r.kx, r.ox), at(2, r.ky, r.oy), at(2, r.kz, r.oz)}};
  return watertight_lanes(q, r.neg_sx, r.neg_sy, r.sz, _mm256_set1_ps(tmin), _mm256_set1_ps(tmax), lanes, t, b1, b2,
                          redo);
}
#endif

}  // namespace frameless
