// A node's single-triangle leaves kept side by side (eight lanes of SoA vertices), so a ray tests
// all it enters in one AVX2 pass of the watertight test instead of visiting each leaf in turn
// (the leaf-heavy bottom of the tree is where a ray spends its triangle tests). Any thread.
#pragma once
#include <cstdint>
#include <type_traits>
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
  // Left unwritten: a big mesh's blocks are hundreds of megabytes, first written (and their pages
  // first touched) by the layout's parallel pass, not zeroed on one thread before it.
  TriangleBlock() {}
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
// and `block`, its parent's `blocked` and `child_blocks` set) and returns the blocks; `nodes` as a
// builder left them (those fields 0), triangles from `leaf_tris` (leaf order). Works in chunks of
// `chunk` nodes through config.parallel_for; the result is the same bytes for any chunk size and
// executor (tests use small chunks).
inline constexpr size_t kBlockChunk = size_t(1) << 14;
std::vector<TriangleBlock> lay_out_triangle_blocks(std::vector<Bvh8Node>& nodes, const std::vector<LeafTriangle>& leaf_tris,
                                                   const AccelConfig& config, size_t chunk = kBlockChunk);

// Asks for a block's cache lines (288 bytes from a 32-byte boundary: five lines at most).
inline void prefetch_block(const TriangleBlock* b) {
  const char* a = reinterpret_cast<const char*>(b);
  for (int line = 0; line < 5; ++line) __builtin_prefetch(a + 64 * line);
}

#if defined(__AVX2__)
// One ray's watertight-test constants, broadcast for the lanes, in the cyclic axes of the
// dominant one kz (x = kz + 1, y = kz + 2, mod 3): unlike the scalar test, the lanes do not swap
// x and y for a negative direction. A swap negates u, v, w, det and the distance's numerator
// exactly (IEEE rounding is symmetric), so t, b1, b2 and every decision come out the same bits.
// With the axes fixed by kz alone, each of its three values gets code with the rows in place
// (lane_hits), instead of nine row addresses worked out per ray.
struct BlockRay {
  __m256 ox, oy, oz, neg_sx, neg_sy, sz;
  int kz = 2;
  // Unset lanes: a traversal sets them before its first test (the set-up waits for one).
  BlockRay() : ox(), oy(), oz(), neg_sx(), neg_sy(), sz() {}
  explicit BlockRay(const TriangleRay& r) : kz(r.kz) {
    const bool swapped = r.kx != (r.kz == 2 ? 0 : r.kz + 1);
    ox = _mm256_set1_ps(swapped ? r.oy : r.ox), oy = _mm256_set1_ps(swapped ? r.ox : r.oy);
    oz = _mm256_set1_ps(r.oz);
    neg_sx = _mm256_set1_ps(-(swapped ? r.sy : r.sx)), neg_sy = _mm256_set1_ps(-(swapped ? r.sx : r.sy));
    sz = _mm256_set1_ps(r.sz);
  }
};

// Block b's triangles relative to the ray, lane j holding slot j's, for a ray whose dominant
// axis is K.
template <int K>
inline LaneTriangle block_lanes(const TriangleBlock& b, const BlockRay& r) {
  constexpr int X = (K + 1) % 3, Y = (K + 2) % 3;
  const auto at = [&](int k, int axis, __m256 o) { return _mm256_sub_ps(_mm256_load_ps(b.v[3 * k + axis]), o); };
  return {{at(0, X, r.ox), at(0, Y, r.oy), at(0, K, r.oz)},
          {at(1, X, r.ox), at(1, Y, r.oy), at(1, K, r.oz)},
          {at(2, X, r.ox), at(2, Y, r.oy), at(2, K, r.oz)}};
}

// Triangles tris[0, n) (1 <= n <= 4, a leaf's, contiguous) relative to the ray in lanes 0..n-1,
// transposed from their LeafTriangles (gathers are slow on some cores); the other lanes repeat
// lane 0 and must be left out of the test's lanes. K: the ray's dominant axis.
template <int K>
inline LaneTriangle leaf_lanes(const LeafTriangle* tris, uint32_t n, const BlockRay& r) {
  constexpr int X = (K + 1) % 3, Y = (K + 2) % 3;
  const float* t0 = &tris[0].p[0].x;
  const float *t1 = n > 1 ? &tris[1].p[0].x : t0, *t2 = n > 2 ? &tris[2].p[0].x : t0, *t3 = n > 3 ? &tris[3].p[0].x : t0;
  // Coordinates 0..7 of the four, four lanes a row (rows 4..7 in the upper halves), then 8.
  const __m256 r0 = _mm256_loadu_ps(t0), r1 = _mm256_loadu_ps(t1), r2 = _mm256_loadu_ps(t2), r3 = _mm256_loadu_ps(t3);
  const __m256 lo01 = _mm256_unpacklo_ps(r0, r1), hi01 = _mm256_unpackhi_ps(r0, r1);
  const __m256 lo23 = _mm256_unpacklo_ps(r2, r3), hi23 = _mm256_unpackhi_ps(r2, r3);
  const __m256 u0 = _mm256_shuffle_ps(lo01, lo23, 0x44), u1 = _mm256_shuffle_ps(lo01, lo23, 0xee);
  const __m256 u2 = _mm256_shuffle_ps(hi01, hi23, 0x44), u3 = _mm256_shuffle_ps(hi01, hi23, 0xee);
  const __m256 rows[9] = {u0, u1, u2, u3, _mm256_permute2f128_ps(u0, u0, 0x01), _mm256_permute2f128_ps(u1, u1, 0x01),
                          _mm256_permute2f128_ps(u2, u2, 0x01), _mm256_permute2f128_ps(u3, u3, 0x01),
                          _mm256_setr_ps(t0[8], t1[8], t2[8], t3[8], t0[8], t0[8], t0[8], t0[8])};
  const auto at = [&](int k, int axis, __m256 o) { return _mm256_sub_ps(rows[3 * k + axis], o); };
  return {{at(0, X, r.ox), at(0, Y, r.oy), at(0, K, r.oz)},
          {at(1, X, r.ox), at(1, Y, r.oy), at(1, K, r.oz)},
          {at(2, X, r.ox), at(2, Y, r.oy), at(2, K, r.oz)}};
}

// Where lane_hits takes its triangles from: block b, or a leaf's first n triangles.
inline auto block_source(const TriangleBlock& b, const BlockRay& r) {
  return [&b, &r](auto k) { return block_lanes<decltype(k)::value>(b, r); };
}
inline auto leaf_source(const LeafTriangle* tris, uint32_t n, const BlockRay& r) {
  return [tris, n, &r](auto k) { return leaf_lanes<decltype(k)::value>(tris, n, r); };
}

// The watertight test of the ray against the lanes `lanes` of the triangles `source` gives
// (block_source, leaf_source; watertight_lanes.h): returns the lanes that hit within [tmin,
// tmax] with t, b1, b2 set, and in `redo` the lanes exactly on an edge in single precision, for
// the scalar test.
template <class Source>
[[gnu::always_inline]]
inline uint32_t lane_hits(const Source& source, const BlockRay& r, uint32_t lanes, float tmin, float tmax,
                          __m256& t, __m256& b1, __m256& b2, uint32_t& redo) {
  const auto run = [&](const LaneTriangle& q) {
    return watertight_lanes(q, r.neg_sx, r.neg_sy, r.sz, _mm256_set1_ps(tmin), _mm256_set1_ps(tmax), lanes, t, b1,
                            b2, redo);
  };
  switch (r.kz) {
    case 0: return run(source(std::integral_constant<int, 0>()));
    case 1: return run(source(std::integral_constant<int, 1>()));
    default: return run(source(std::integral_constant<int, 2>()));
  }
}
#endif

}  // namespace frameless
