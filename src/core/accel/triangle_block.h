// A node's single-triangle leaves kept side by side (eight lanes of SoA vertices), so a ray tests
// all it enters in one AVX2 pass of the watertight test instead of visiting each leaf in turn
// (the leaf-heavy bottom of the tree is where a ray spends its triangle tests). Any thread.
#pragma once
#include <cstdint>
#include <vector>

#include "core/accel/accel_types.h"
#include "core/accel/bvh_node.h"
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

namespace block_detail {
inline __m256 mul8(__m256 a, __m256 b) {  // a product never contracted into a following add
  __m256 p = _mm256_mul_ps(a, b);
  asm("" : "+x"(p));
  return p;
}
}  // namespace block_detail

// intersect_triangle for the lanes in `lanes`, the same operations in the same order, so each
// lane's answer is the scalar test's bit for bit. Returns the lanes that hit within
// [tmin, tmax] with t, b1, b2 set; lanes exactly on an edge in single precision are returned in
// `redo` instead, for the scalar test (which decides them in double).
inline uint32_t block_hits(const TriangleBlock& b, const BlockRay& r, uint32_t lanes, float tmin,
                           float tmax, __m256& t, __m256& b1, __m256& b2, uint32_t& redo) {
  using block_detail::mul8;
  const auto row = [&](int k, int axis) { return _mm256_load_ps(b.v[3 * k + axis]); };
  const __m256 a_x = _mm256_sub_ps(row(0, r.kx), r.ox), a_y = _mm256_sub_ps(row(0, r.ky), r.oy),
               a_z = _mm256_sub_ps(row(0, r.kz), r.oz);
  const __m256 b_x = _mm256_sub_ps(row(1, r.kx), r.ox), b_y = _mm256_sub_ps(row(1, r.ky), r.oy),
               b_z = _mm256_sub_ps(row(1, r.kz), r.oz);
  const __m256 c_x = _mm256_sub_ps(row(2, r.kx), r.ox), c_y = _mm256_sub_ps(row(2, r.ky), r.oy),
               c_z = _mm256_sub_ps(row(2, r.kz), r.oz);
  const __m256 ax = _mm256_fmadd_ps(r.neg_sx, a_z, a_x), ay = _mm256_fmadd_ps(r.neg_sy, a_z, a_y);
  const __m256 bx = _mm256_fmadd_ps(r.neg_sx, b_z, b_x), by = _mm256_fmadd_ps(r.neg_sy, b_z, b_y);
  const __m256 cx = _mm256_fmadd_ps(r.neg_sx, c_z, c_x), cy = _mm256_fmadd_ps(r.neg_sy, c_z, c_y);
  const __m256 u = _mm256_sub_ps(mul8(cx, by), mul8(cy, bx));
  const __m256 v = _mm256_sub_ps(mul8(ax, cy), mul8(ay, cx));
  const __m256 w = _mm256_sub_ps(mul8(bx, ay), mul8(by, ax));
  const __m256 zero = _mm256_setzero_ps();
  redo = lanes & uint32_t(_mm256_movemask_ps(_mm256_or_ps(
                     _mm256_cmp_ps(u, zero, _CMP_EQ_OQ),
                     _mm256_or_ps(_mm256_cmp_ps(v, zero, _CMP_EQ_OQ), _mm256_cmp_ps(w, zero, _CMP_EQ_OQ)))));
  const __m256 has_neg = _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_LT_OQ),
                                      _mm256_or_ps(_mm256_cmp_ps(v, zero, _CMP_LT_OQ), _mm256_cmp_ps(w, zero, _CMP_LT_OQ)));
  const __m256 has_pos = _mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_GT_OQ),
                                      _mm256_or_ps(_mm256_cmp_ps(v, zero, _CMP_GT_OQ), _mm256_cmp_ps(w, zero, _CMP_GT_OQ)));
  const __m256 det = _mm256_add_ps(_mm256_add_ps(u, v), w);
  const __m256 az = mul8(r.sz, a_z), bz = mul8(r.sz, b_z), cz = mul8(r.sz, c_z);
  const __m256 tt = _mm256_fmadd_ps(u, az, _mm256_fmadd_ps(v, bz, mul8(w, cz)));
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 adet = _mm256_andnot_ps(sign, det);
  const __m256 stt = _mm256_xor_ps(tt, _mm256_and_ps(det, sign));  // det == -0 is rejected below
  const __m256 in_range = _mm256_and_ps(_mm256_cmp_ps(stt, mul8(_mm256_set1_ps(tmin), adet), _CMP_GE_OQ),
                                        _mm256_cmp_ps(stt, mul8(_mm256_set1_ps(tmax), adet), _CMP_LE_OQ));
  const __m256 ok = _mm256_and_ps(
      _mm256_andnot_ps(_mm256_and_ps(has_neg, has_pos), _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ)), in_range);
  const uint32_t hit = uint32_t(_mm256_movemask_ps(ok)) & lanes & ~redo;
  if (hit == 0) return 0;  // most tests miss: skip the division
  const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
  t = mul8(tt, inv);
  b1 = mul8(v, inv);
  b2 = mul8(w, inv);
  return hit;
}
#endif

}  // namespace frameless
