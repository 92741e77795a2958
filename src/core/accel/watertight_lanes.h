// The watertight ray/triangle test (core/geometry/intersect_triangle.h) in eight AVX2 lanes, the
// scalar operations in the same order, so each lane's answer is the scalar test's bit for bit:
// eight rays against one triangle (packets) or one ray against eight triangles (triangle
// blocks). Any thread.
#pragma once
#if defined(__AVX2__)
#include <immintrin.h>

#include <cstdint>

namespace frameless {

// a * b rounded, hidden from contraction: GCC's intrinsics are plain vector arithmetic, which
// -ffp-contract=fast would fuse into FMAs the scalar test (core/base/fused_float.h) does not
// perform.
inline __m256 mul8(__m256 a, __m256 b) {
  __m256 p = _mm256_mul_ps(a, b);
  asm("" : "+x"(p));
  return p;
}

// A triangle's vertices minus the ray origin, in the ray's permuted axes (x = kx, y = ky, z = kz
// of TriangleRay), lane by lane.
struct LaneTriangle {
  __m256 a[3], b[3], c[3];
};

// The test in the lanes `lanes`, with the rays' shear (-sx, -sy, sz) and intervals [tmin, tmax].
// Returns the lanes that hit with t, b1, b2 set; lanes exactly on an edge in single precision are
// returned in `redo` instead, for the scalar test (which decides them in double).
[[gnu::always_inline]]
inline uint32_t watertight_lanes(const LaneTriangle& q, __m256 neg_sx, __m256 neg_sy, __m256 sz, __m256 tmin,
                                 __m256 tmax, uint32_t lanes, __m256& t, __m256& b1, __m256& b2, uint32_t& redo) {
  const __m256 ax = _mm256_fmadd_ps(neg_sx, q.a[2], q.a[0]), ay = _mm256_fmadd_ps(neg_sy, q.a[2], q.a[1]);
  const __m256 bx = _mm256_fmadd_ps(neg_sx, q.b[2], q.b[0]), by = _mm256_fmadd_ps(neg_sy, q.b[2], q.b[1]);
  const __m256 cx = _mm256_fmadd_ps(neg_sx, q.c[2], q.c[0]), cy = _mm256_fmadd_ps(neg_sy, q.c[2], q.c[1]);
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
  const __m256 az = mul8(sz, q.a[2]), bz = mul8(sz, q.b[2]), cz = mul8(sz, q.c[2]);
  const __m256 tt = _mm256_fmadd_ps(u, az, _mm256_fmadd_ps(v, bz, mul8(w, cz)));
  // The distance against the interval without dividing (sign of det folded in; det == -0 is
  // rejected below).
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 adet = _mm256_andnot_ps(sign, det);
  const __m256 stt = _mm256_xor_ps(tt, _mm256_and_ps(det, sign));
  const __m256 in_range = _mm256_and_ps(_mm256_cmp_ps(stt, mul8(tmin, adet), _CMP_GE_OQ),
                                        _mm256_cmp_ps(stt, mul8(tmax, adet), _CMP_LE_OQ));
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

}  // namespace frameless
#endif
