// Four-float vectors (x, y, z and a spare lane) for the per-primitive work of the BVH builders
// (bvh_build.cpp, bvh_build_spheres*.cpp): SSE where there is SSE, plain floats otherwise, with
// the same results (min/max return their second operand when unordered, as minps/maxps do).
#pragma once
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "core/base/types.h"

namespace frameless::bvh_f4 {

#if defined(__SSE2__)
struct F4 {
  __m128 v;
};
inline F4 load4(const float* p) { return {_mm_loadu_ps(p)}; }
inline F4 splat4(float x) { return {_mm_set1_ps(x)}; }
inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
inline F4 min4(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
inline F4 max4(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
inline F4 abs_w4(F4 a) {  // |a.w| in every lane
  const __m128 w = _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(3, 3, 3, 3));
  return {_mm_andnot_ps(_mm_set1_ps(-0.0f), w)};
}
// a with its w lane zeroed (a bit mask: no arithmetic on whatever the lane held).
inline F4 xyz0(F4 a) {
  return {_mm_and_ps(a.v, _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)))};
}
inline bool xyz_zero4(F4 a) {
  return (_mm_movemask_ps(_mm_cmpeq_ps(a.v, _mm_setzero_ps())) & 7) == 7;
}
inline void store4(float* p, F4 a) { _mm_storeu_ps(p, a.v); }
// m ? a : b without a branch.
inline F4 select4(bool m, F4 a, F4 b) {
  const __m128 k = _mm_castsi128_ps(_mm_set1_epi32(-int(m)));
  return {_mm_or_ps(_mm_and_ps(k, a.v), _mm_andnot_ps(k, b.v))};
}
// Bin of each lane: (c - lo) * scale clamped to [0, kmax] (NaN to 0), truncated.
inline void bin4(F4 c, F4 lo, F4 scale, float kmax, int* out) {
  const __m128 k = _mm_mul_ps(_mm_sub_ps(c.v, lo.v), scale.v);
  const __m128 kc = _mm_min_ps(_mm_max_ps(k, _mm_setzero_ps()), _mm_set1_ps(kmax));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(kc));
}
// Half the surface area of the box [lo, hi] (x, y, z lanes): 0 when it is empty on some axis.
inline float half_area4(F4 lo, F4 hi) {
  const __m128 d = _mm_sub_ps(hi.v, lo.v);
  const __m128 e = _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1));  // y z x
  const __m128 p = _mm_mul_ps(d, e);                                // xy yz zx
  alignas(16) float f[4], g[4];
  _mm_store_ps(f, p);
  _mm_store_ps(g, d);
  if (!(g[0] >= 0.0f && g[1] >= 0.0f && g[2] >= 0.0f)) return 0.0f;
  return f[0] + f[1] + f[2];
}
#else
struct F4 {
  float v[4];
};
inline F4 load4(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline F4 splat4(float x) { return {{x, x, x, x}}; }
#define FRAMELESS_F4_OP(name, expr)                                   \
  inline F4 name(F4 a, F4 b) {                                        \
    F4 r;                                                             \
    for (int i = 0; i < 4; ++i) r.v[i] = expr;                        \
    return r;                                                         \
  }
FRAMELESS_F4_OP(operator+, a.v[i] + b.v[i])
FRAMELESS_F4_OP(operator-, a.v[i] - b.v[i])
FRAMELESS_F4_OP(operator*, a.v[i] * b.v[i])
FRAMELESS_F4_OP(min4, a.v[i] < b.v[i] ? a.v[i] : b.v[i])
FRAMELESS_F4_OP(max4, a.v[i] > b.v[i] ? a.v[i] : b.v[i])
#undef FRAMELESS_F4_OP
inline F4 abs_w4(F4 a) { return splat4(std::abs(a.v[3])); }
inline F4 xyz0(F4 a) {
  a.v[3] = 0.0f;
  return a;
}
inline bool xyz_zero4(F4 a) { return a.v[0] == 0.0f && a.v[1] == 0.0f && a.v[2] == 0.0f; }
inline void store4(float* p, F4 a) {
  for (int i = 0; i < 4; ++i) p[i] = a.v[i];
}
inline F4 select4(bool m, F4 a, F4 b) { return m ? a : b; }
inline void bin4(F4 c, F4 lo, F4 scale, float kmax, int* out) {
  for (int i = 0; i < 4; ++i) {
    float k = (c.v[i] - lo.v[i]) * scale.v[i];
    k = k > 0.0f ? k : 0.0f;
    out[i] = int(k < kmax ? k : kmax);
  }
}
inline float half_area4(F4 lo, F4 hi) {
  const float dx = hi.v[0] - lo.v[0], dy = hi.v[1] - lo.v[1], dz = hi.v[2] - lo.v[2];
  if (!(dx >= 0.0f && dy >= 0.0f && dz >= 0.0f)) return 0.0f;
  return dx * dy + dy * dz + dz * dx;
}
#endif


// A box as one value for min-only updates: lo and -hi (so growing is one min). One AVX register
// where there is AVX.
#if defined(__AVX__)
struct Box8 {
  __m256 v;
};
inline Box8 empty8() { return {_mm256_set1_ps(kInfinity)}; }
inline Box8 pack8(F4 lo, F4 hi) {
  const __m128 nhi = _mm_xor_ps(hi.v, _mm_set1_ps(-0.0f));
  return {_mm256_insertf128_ps(_mm256_castps128_ps256(lo.v), nhi, 1)};
}
inline Box8 min8(Box8 a, Box8 b) { return {_mm256_min_ps(a.v, b.v)}; }
inline F4 lo8(Box8 a) { return {_mm256_castps256_ps128(a.v)}; }
inline F4 hi8(Box8 a) {
  return {_mm_xor_ps(_mm256_extractf128_ps(a.v, 1), _mm_set1_ps(-0.0f))};
}
#else
struct Box8 {
  F4 lo, hi;
};
inline Box8 empty8() { return {splat4(kInfinity), splat4(-kInfinity)}; }
inline Box8 pack8(F4 lo, F4 hi) { return {lo, hi}; }
inline Box8 min8(Box8 a, Box8 b) { return {min4(a.lo, b.lo), max4(a.hi, b.hi)}; }
inline F4 lo8(Box8 a) { return a.lo; }
inline F4 hi8(Box8 a) { return a.hi; }
#endif

inline F4 f4(const Vec3& v) {
  const float f[4] = {v.x, v.y, v.z, 0.0f};
  return load4(f);
}

inline Vec3 xyz(F4 a) {
  float f[4];
  store4(f, a);
  return Vec3(f[0], f[1], f[2]);
}

// Running bounds in F4 form.
struct Box4 {
  F4 lo = splat4(kInfinity), hi = splat4(-kInfinity);
  void grow(F4 l, F4 h) {
    lo = min4(lo, l);
    hi = max4(hi, h);
  }
  void grow(F4 p) { grow(p, p); }
  void grow(const Box4& b) { grow(b.lo, b.hi); }
  float half_area() const { return half_area4(lo, hi); }
};


// One step of a split sweep on one axis: the bounds and count of what it adds.
struct SweepItem {
  F4 lo, hi;
  uint32_t count;
};

// The best SAH split of `steps` ordered groups per axis (bins, or single primitives in centroid
// order) into a prefix [0, pos) and a suffix [pos, steps): cost = half_area(prefix bounds) *
// prefix count + half_area(suffix bounds) * suffix count, over the axes with use[a], both sides
// non-empty. get(a, k) returns the SweepItem of step k on axis a. Ties go to the lowest axis, then
// the lowest pos; axis -1 when no split has a finite cost. kMaxSteps bounds steps.
struct SweepResult {
  int axis = -1;
  int pos = 0;
  float cost = kInfinity;
};

template <int kMaxSteps, class Get>
SweepResult sweep3(int steps, const bool use[3], Get&& get) {
  SweepResult best;
#if defined(__SSE2__)
  // The three axes side by side in the lanes of one vector.
  auto area3 = [](const F4* lo, const F4* hi) {
    const __m128 d0 = _mm_sub_ps(hi[0].v, lo[0].v), d1 = _mm_sub_ps(hi[1].v, lo[1].v),
                 d2 = _mm_sub_ps(hi[2].v, lo[2].v), d3 = _mm_setzero_ps();
    const __m128 t0 = _mm_unpacklo_ps(d0, d1), t1 = _mm_unpacklo_ps(d2, d3);
    const __m128 t2 = _mm_unpackhi_ps(d0, d1), t3 = _mm_unpackhi_ps(d2, d3);
    const __m128 dx = _mm_movelh_ps(t0, t1), dy = _mm_movehl_ps(t1, t0),
                 dz = _mm_movelh_ps(t2, t3);
    const __m128 zero = _mm_setzero_ps();
    const __m128 ok = _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(dx, zero), _mm_cmpge_ps(dy, zero)),
                                 _mm_cmpge_ps(dz, zero));
    const __m128 a = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dy), _mm_mul_ps(dy, dz)),
                                _mm_mul_ps(dz, dx));
    return _mm_and_ps(a, ok);
  };
  const __m128 inf = _mm_set1_ps(kInfinity);
  __m128 right_cost[kMaxSteps];
  F4 lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = splat4(kInfinity), hi[a] = splat4(-kInfinity);
  __m128i cnt = _mm_setzero_si128();
  for (int k = steps - 1; k > 0; --k) {
    uint32_t c[3];
    for (int a = 0; a < 3; ++a) {
      const SweepItem e = get(a, k);
      lo[a] = min4(lo[a], e.lo);
      hi[a] = max4(hi[a], e.hi);
      c[a] = e.count;
    }
    cnt = _mm_add_epi32(cnt, _mm_set_epi32(0, int(c[2]), int(c[1]), int(c[0])));
    const __m128 some = _mm_castsi128_ps(_mm_cmpgt_epi32(cnt, _mm_setzero_si128()));
    const __m128 cost = _mm_mul_ps(area3(lo, hi), _mm_cvtepi32_ps(cnt));
    right_cost[k] = _mm_or_ps(_mm_and_ps(some, cost), _mm_andnot_ps(some, inf));
  }
  const __m128 usable = _mm_castsi128_ps(
      _mm_set_epi32(0, use[2] ? -1 : 0, use[1] ? -1 : 0, use[0] ? -1 : 0));
  for (int a = 0; a < 3; ++a) lo[a] = splat4(kInfinity), hi[a] = splat4(-kInfinity);
  cnt = _mm_setzero_si128();
  __m128 best_cost = inf;
  __m128i best_k = _mm_setzero_si128();
  for (int k = 1; k < steps; ++k) {
    uint32_t c[3];
    for (int a = 0; a < 3; ++a) {
      const SweepItem e = get(a, k - 1);
      lo[a] = min4(lo[a], e.lo);
      hi[a] = max4(hi[a], e.hi);
      c[a] = e.count;
    }
    cnt = _mm_add_epi32(cnt, _mm_set_epi32(0, int(c[2]), int(c[1]), int(c[0])));
    const __m128 some =
        _mm_and_ps(usable, _mm_castsi128_ps(_mm_cmpgt_epi32(cnt, _mm_setzero_si128())));
    __m128 cost =
        _mm_add_ps(_mm_mul_ps(area3(lo, hi), _mm_cvtepi32_ps(cnt)), right_cost[k]);
    cost = _mm_or_ps(_mm_and_ps(some, cost), _mm_andnot_ps(some, inf));
    const __m128 lt = _mm_cmplt_ps(cost, best_cost);
    best_cost = _mm_or_ps(_mm_and_ps(lt, cost), _mm_andnot_ps(lt, best_cost));
    best_k = _mm_or_si128(_mm_and_si128(_mm_castps_si128(lt), _mm_set1_epi32(k)),
                          _mm_andnot_si128(_mm_castps_si128(lt), best_k));
  }
  alignas(16) float bc[4];
  alignas(16) int bk[4];
  _mm_store_ps(bc, best_cost);
  _mm_store_si128(reinterpret_cast<__m128i*>(bk), best_k);
  for (int a = 0; a < 3; ++a)
    if (use[a] && bc[a] < best.cost) best.cost = bc[a], best.axis = a, best.pos = bk[a];
#else
  for (int a = 0; a < 3; ++a) {
    if (!use[a]) continue;
    float right_cost[kMaxSteps];
    Box4 acc;
    uint32_t cnt = 0;
    for (int k = steps - 1; k > 0; --k) {
      const SweepItem e = get(a, k);
      acc.grow(e.lo, e.hi);
      cnt += e.count;
      right_cost[k] = cnt ? acc.half_area() * float(cnt) : kInfinity;
    }
    acc = Box4();
    cnt = 0;
    for (int k = 1; k < steps; ++k) {
      const SweepItem e = get(a, k - 1);
      acc.grow(e.lo, e.hi);
      cnt += e.count;
      if (cnt == 0) continue;
      const float cost = acc.half_area() * float(cnt) + right_cost[k];
      if (cost < best.cost) best.cost = cost, best.axis = a, best.pos = k;
    }
  }
#endif
  return best;
}

}  // namespace frameless::bvh_f4
