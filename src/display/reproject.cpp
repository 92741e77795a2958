#include "display/reproject.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include "display/reproject_keys.h"

namespace frameless {
using namespace reproject_keys;

// The farther of two landed pixels (kNone: none); a tie goes to the lower pixel index, so both
// searches below pick the same pixel.
uint32_t Reprojector::farther(uint32_t a, uint32_t b) const {
  if (a == kNone) return b;
  if (b == kNone) return a;
  const uint32_t da = depth_bits(key_[a]), db = depth_bits(key_[b]);
  return db > da || (db == da && b < a) ? b : a;
}

// Whether farthest_in_window takes a window row (at most 7 keys) per vector compare.
bool Reprojector::vector_window(int r) const {
#if defined(__AVX512F__) || defined(__AVX2__)
  return vectorized_ && r <= 3;
#else
  (void)r;
  return false;
#endif
}

// The farthest landed pixel within r of (x, y), one window per hole.
uint32_t Reprojector::farthest_in_window(int x, int y, int w, int h, int r) const {
#if defined(__AVX512F__)
  if (vector_window(r)) {  // a row of the window (at most 7 keys) in one vector: the hot path of large moves
    const int x0 = std::max(0, x - r), x1 = std::min(w - 1, x + r);
    const __mmask8 lanes = __mmask8((1u << (x1 - x0 + 1)) - 1u);
    const __m512i hole = _mm512_set1_epi64(int64_t(kHole));
    uint32_t best = kNone, best_depth = 0;
    for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy) {
      const size_t base = size_t(yy) * size_t(w) + size_t(x0);
      const __m512i keys = _mm512_maskz_loadu_epi64(lanes, &key_[base]);
      const __mmask8 landed = _mm512_mask_cmpneq_epu64_mask(lanes, keys, hole);
      if (!landed) continue;
      const __m512i depth = _mm512_srli_epi64(keys, 32);
      const uint64_t d = _mm512_mask_reduce_max_epu64(landed, depth);
      // Rows run in pixel order, so the first lane of the farthest depth and, across rows, a
      // strictly farther depth keep farther()'s tie rule (the lower pixel).
      if (best != kNone && uint32_t(d) <= best_depth) continue;
      const __mmask8 at = _mm512_mask_cmpeq_epu64_mask(landed, depth, _mm512_set1_epi64(int64_t(d)));
      best = uint32_t(base) + uint32_t(__builtin_ctz(at));
      best_depth = uint32_t(d);
    }
    return best;
  }
#elif defined(__AVX2__)
  if (vector_window(r)) return farthest_in_window4(x, y, w, h, r);
#endif
  uint32_t best = kNone;
  for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy)
    for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx) {
      const uint32_t q = uint32_t(yy) * uint32_t(w) + uint32_t(xx);
      if (key_[q] != kHole) best = farther(best, q);
    }
  return best;
}

// The same as two 1D passes, cheaper for many holes: per row (computed once, when first needed),
// the farthest landed pixel within r columns of each pixel (van Herk's block prefix and suffix
// maxima: three comparisons a pixel), then the farthest of those within r rows.
uint32_t Reprojector::farthest_in_rows(int x, int y, int w, int h, int r) {
  const int k = 2 * r + 1, padded = w + 2 * r;
  const auto row = [&](int yy) {
    if (row_done_[size_t(yy)]) return;
    row_done_[size_t(yy)] = 1;
    const size_t base = size_t(yy) * size_t(w);
    const auto at = [&](int i) {  // padded column i (i - r in the image), kNone outside
      const int xx = i - r;
      return xx < 0 || xx >= w || key_[base + size_t(xx)] == kHole ? kNone : uint32_t(base + size_t(xx));
    };
    for (int i = 0; i < padded; ++i)
      prefix_[size_t(i)] = i % k == 0 ? at(i) : farther(prefix_[size_t(i) - 1], at(i));
    for (int i = padded - 1; i >= 0; --i)
      suffix_[size_t(i)] = (i % k == k - 1 || i == padded - 1) ? at(i) : farther(at(i), suffix_[size_t(i) + 1]);
    // Column xx's window is padded [xx, xx + 2r]: a block's suffix and the next block's prefix.
    for (int xx = 0; xx < w; ++xx)
      row_best_[base + size_t(xx)] = farther(suffix_[size_t(xx)], prefix_[size_t(std::min(xx + 2 * r, padded - 1))]);
  };
  uint32_t best = kNone;
  for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy) {
    row(yy);
    best = farther(best, row_best_[size_t(yy) * size_t(w) + size_t(x)]);
  }
  return best;
}

#if defined(__AVX512F__)
// Sixteen of the engine's world points (EngineBatch) projected as Projector does (the same fused
// operations, so the same pixels, depths and fractions) and landed as land() lands them.
void Reprojector::land_engine16(const Projector& to, const EngineBatch& b, int w) {
  const __m512 zero = _mm512_setzero_ps();
  const __m512i obj = _mm512_load_si512(b.object);
  const __mmask16 sky = _mm512_cmpeq_epi32_mask(obj, _mm512_set1_epi32(int(kPointSky)));
  const __mmask16 none = _mm512_cmpeq_epi32_mask(obj, _mm512_set1_epi32(int(kPointNone)));
  const __mmask16 moving = _mm512_cmpge_epu32_mask(obj, _mm512_set1_epi32(int(kPointDynamic)));
  // d = p - eye, the sky's p itself (a direction)
  const auto diff = [&](const float* c, float e) {
    const __m512 v = _mm512_load_ps(c);
    return _mm512_mask_sub_ps(v, __mmask16(~sky), v, _mm512_set1_ps(e));
  };
  const __m512 dx = diff(b.x, to.eye.x), dy = diff(b.y, to.eye.y), dz = diff(b.z, to.eye.z);
  const auto dot = [&](const Vec3& a) {  // dot_exact(d, a)
    return _mm512_fmadd_ps(dx, _mm512_set1_ps(a.x),
                           _mm512_fmadd_ps(dy, _mm512_set1_ps(a.y), _mm512_mul_ps(dz, _mm512_set1_ps(a.z))));
  };
  const __m512 z = dot(to.w);
  const __m512 inv = _mm512_div_ps(_mm512_set1_ps(1.0f), z);
  const __m512 sx = _mm512_fmadd_ps(dot(to.x), inv, _mm512_set1_ps(to.cx));
  const __m512 sy = _mm512_fnmadd_ps(dot(to.y), inv, _mm512_set1_ps(to.cy));
  __mmask16 in = __mmask16(~none & ((1u << b.count) - 1u)) & _mm512_cmp_ps_mask(z, zero, _CMP_GT_OQ);
  in &= _mm512_cmp_ps_mask(sx, zero, _CMP_GE_OQ) & _mm512_cmp_ps_mask(sx, _mm512_set1_ps(to.width), _CMP_LT_OQ);
  in &= _mm512_cmp_ps_mask(sy, zero, _CMP_GE_OQ) & _mm512_cmp_ps_mask(sy, _mm512_set1_ps(to.height), _CMP_LT_OQ);
  if (!in) return;
  // view_kind_of: static 2, sky 1, moving 3 (none never lands)
  __m512i kind = _mm512_mask_mov_epi32(_mm512_set1_epi32(int(kViewStatic)), sky, _mm512_set1_epi32(int(kViewSky)));
  kind = _mm512_mask_mov_epi32(kind, moving, _mm512_set1_epi32(int(kViewMoving)));
  const __m512i ix = _mm512_cvttps_epi32(sx), iy = _mm512_cvttps_epi32(sy);
  const __m512 scale = _mm512_set1_ps(kViewFractionScale);
  const __m512i qx = _mm512_cvttps_epi32(_mm512_mul_ps(_mm512_sub_ps(sx, _mm512_cvtepi32_ps(ix)), scale));
  const __m512i qy = _mm512_cvttps_epi32(_mm512_mul_ps(_mm512_sub_ps(sy, _mm512_cvtepi32_ps(iy)), scale));
  alignas(64) uint32_t target[16], word[16], depth[16];
  _mm512_store_si512(target, _mm512_add_epi32(_mm512_mullo_epi32(iy, _mm512_set1_epi32(w)), ix));
  _mm512_store_si512(word, _mm512_or_si512(_mm512_or_si512(qx, _mm512_slli_epi32(qy, kViewFractionBits)),
                                           _mm512_slli_epi32(kind, kViewKindShift)));
  _mm512_store_ps(reinterpret_cast<float*>(depth),
                  _mm512_mask_mov_ps(z, sky, _mm512_set1_ps(std::numeric_limits<float>::infinity())));
  land_lanes(in, b, target, depth, word);
}

// The splat 16 pixels a step: their view points split into depths and bits, moved as ViewMove
// does (the same fused operations, so the same pixels, depths and fractions), then each landed
// point's key kept if nearer (a minimum: the lanes' order does not matter). Unmarked pixels (the
// engine's world points, few while moving) go to splat_one. Returns the pixels done.
size_t Reprojector::splat16(const ViewMove& mv, const SlotImage& from, int w) {
  if (w < 16) return 0;  // a step's pixels span at most two rows
  const size_t n = from.pixels() / 16 * 16;
  const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odd = _mm512_add_epi32(even, _mm512_set1_epi32(1));
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i fraction = _mm512_set1_epi32(int(kViewFractionMask)), width = _mm512_set1_epi32(w);
  const __m512 half = _mm512_set1_ps(0.5f), step = _mm512_set1_ps(kViewFractionStep);
  const __m512 zero = _mm512_setzero_ps(), scale = _mm512_set1_ps(kViewFractionScale);
  const __m512 inf = _mm512_set1_ps(std::numeric_limits<float>::infinity());
  const __m512i sky = _mm512_set1_epi32(int(kViewSky));
  alignas(64) uint32_t target[16];
  alignas(64) uint64_t mine[16];
  EngineBatch batch;
  const __m512i spare = _mm512_set1_epi32(int(from.pixels()));  // key_[pixels]: written, never read
  uint32_t x0 = 0, y0 = 0;  // pixel p's column and row
  for (size_t p = 0; p < n; p += 16, x0 += 16) {
    if (x0 >= uint32_t(w)) x0 -= uint32_t(w), ++y0;
    __mmask16 engine = 0;
    if (from.engine_points) {  // unmarked pixels show the engine's newest point (few while moving)
      // Scattered among the marked ones and last written by a render thread's core: asked for
      // 64 pixels ahead.
      if (p + 64 + 16 <= n) {
        const __m128i ahead = _mm_loadu_si128(reinterpret_cast<const __m128i*>(from.marks + p + 64));
        for (unsigned m = _mm_cmpeq_epi8_mask(ahead, _mm_setzero_si128()); m; m &= m - 1u)
          __builtin_prefetch(from.engine_points + p + 64 + __builtin_ctz(m));
      }
      engine = _mm_cmpeq_epi8_mask(_mm_loadu_si128(reinterpret_cast<const __m128i*>(from.marks + p)), _mm_setzero_si128());
    }
    const float* f = reinterpret_cast<const float*>(from.points + p);
    const __m512 a = _mm512_loadu_ps(f), b = _mm512_loadu_ps(f + 16);
    const __m512 depth = _mm512_permutex2var_ps(a, even, b);
    const __m512i bits = _mm512_castps_si512(_mm512_permutex2var_ps(a, odd, b));
    const __m512i kind = _mm512_srli_epi32(bits, kViewKindShift);
    __m512i x = _mm512_add_epi32(_mm512_set1_epi32(int(x0)), lane);
    const __mmask16 wrap = _mm512_cmpge_epu32_mask(x, width);
    x = _mm512_mask_sub_epi32(x, wrap, x, width);
    const __m512i y = _mm512_mask_add_epi32(_mm512_set1_epi32(int(y0)), wrap, _mm512_set1_epi32(int(y0)), _mm512_set1_epi32(1));
    // view_position
    const __m512 X = _mm512_fmadd_ps(_mm512_add_ps(_mm512_cvtepi32_ps(_mm512_and_si512(bits, fraction)), half), step,
                                     _mm512_cvtepi32_ps(x));
    const __m512 Y = _mm512_fmadd_ps(
        _mm512_add_ps(_mm512_cvtepi32_ps(_mm512_and_si512(_mm512_srli_epi32(bits, kViewFractionBits), fraction)), half),
        step, _mm512_cvtepi32_ps(y));
    const __mmask16 is_sky = _mm512_cmpeq_epi32_mask(kind, sky);
    const auto axis = [&](int i) {
      const __m512 k = _mm512_fmadd_ps(_mm512_set1_ps(mv.k2[i]), Y,
                                       _mm512_fmadd_ps(_mm512_set1_ps(mv.k1[i]), X, _mm512_set1_ps(mv.k0[i])));
      return _mm512_mask_mov_ps(_mm512_fmadd_ps(depth, k, _mm512_set1_ps(mv.t[i])), is_sky, k);
    };
    const __m512 z = axis(0);
    const __m512 inv = _mm512_div_ps(_mm512_set1_ps(1.0f), z);
    const __m512 sx = _mm512_fmadd_ps(axis(1), inv, _mm512_set1_ps(mv.to.cx));
    const __m512 sy = _mm512_fnmadd_ps(axis(2), inv, _mm512_set1_ps(mv.to.cy));
    __mmask16 landed = _mm512_mask_cmpneq_epi32_mask(__mmask16(~engine), kind, _mm512_setzero_si512()) &
                       _mm512_cmp_ps_mask(z, zero, _CMP_GT_OQ);
    landed &= _mm512_cmp_ps_mask(sx, zero, _CMP_GE_OQ) & _mm512_cmp_ps_mask(sx, _mm512_set1_ps(mv.to.width), _CMP_LT_OQ);
    landed &= _mm512_cmp_ps_mask(sy, zero, _CMP_GE_OQ) & _mm512_cmp_ps_mask(sy, _mm512_set1_ps(mv.to.height), _CMP_LT_OQ);
    if (landed) {
      const __m512i ix = _mm512_cvttps_epi32(sx), iy = _mm512_cvttps_epi32(sy);
      _mm512_store_si512(target, _mm512_mask_blend_epi32(landed, spare, _mm512_add_epi32(_mm512_mullo_epi32(iy, width), ix)));
      const __m512i depths = _mm512_castps_si512(_mm512_mask_mov_ps(z, is_sky, inf));
      const __m512i source = _mm512_add_epi32(_mm512_set1_epi32(int(p)), lane);
      const auto keys = [](__m256i d, __m256i s) {
        return _mm512_or_si512(_mm512_slli_epi64(_mm512_cvtepu32_epi64(d), 32), _mm512_cvtepu32_epi64(s));
      };
      _mm512_store_si512(mine, keys(_mm512_castsi512_si256(depths), _mm512_castsi512_si256(source)));
      _mm512_store_si512(mine + 8, keys(_mm512_extracti64x4_epi64(depths, 1), _mm512_extracti64x4_epi64(source, 1)));
      // view_bits
      const __m512i qx = _mm512_cvttps_epi32(_mm512_mul_ps(_mm512_sub_ps(sx, _mm512_cvtepi32_ps(ix)), scale));
      const __m512i qy = _mm512_cvttps_epi32(_mm512_mul_ps(_mm512_sub_ps(sy, _mm512_cvtepi32_ps(iy)), scale));
      const __m512i word = _mm512_or_si512(_mm512_or_si512(qx, _mm512_slli_epi32(qy, kViewFractionBits)),
                                           _mm512_slli_epi32(kind, kViewKindShift));
      _mm512_mask_storeu_epi32(moved_.data() + p, landed, word);
      // Every lane's key kept if nearer, the lanes that landed nowhere into the spare key past
      // the image: no branch a lane (a loop over the landed lanes mispredicted its exit).
#pragma GCC unroll 16
      for (int i = 0; i < 16; ++i) {
        uint64_t& k = key_[target[i]];
        k = std::min(k, mine[i]);
      }
    }
    // Their world points read now (each under its lock), projected sixteen at a time: one at a
    // time they cost three times the reads (66 against 27 cycles a point, 47 k points a change).
    for (unsigned m = engine; m; m &= m - 1u) {
      const size_t q = p + __builtin_ctz(m);
      if (batch.add(engine_point(from, q), uint32_t(q)) == 16) land_engine16(mv.to, batch, w), batch.count = 0;
    }
  }
  if (batch.count) land_engine16(mv.to, batch, w);
  return n;
}
#endif

// Hole t (nothing landed): a crack inside a magnified surface when it has landed neighbours of
// about one depth on opposite sides; it takes the farther of such a pair (the farthest pair's),
// else it waits for the disocclusion search. Fills are applied after the pass.
void Reprojector::crack(uint32_t t, int w, int h) {
  const int x = int(t % uint32_t(w)), y = int(t / uint32_t(w));
  const bool inside = x > 0 && y > 0 && x < w - 1 && y < h - 1;
  uint64_t best = kHole;
  for (const auto& d : kOpposite) {
    if (!inside && (x - d[0] < 0 || x + d[0] >= w || y - std::abs(d[1]) < 0 || y + std::abs(d[1]) >= h)) continue;
    const int64_t off = int64_t(d[1]) * w + d[0];
    const uint64_t kp = key_[size_t(int64_t(t) + off)], kq = key_[size_t(int64_t(t) - off)];
    if (kp == kHole || kq == kHole) continue;
    const float dp = key_depth(kp), dq = key_depth(kq);
    if (std::max(dp, dq) > std::min(dp, dq) * 1.05f) continue;  // an edge between two surfaces, not a crack
    const uint64_t f = dp >= dq ? kp : kq;
    if (best == kHole || depth_bits(f) > depth_bits(best)) best = f;
  }
  if (best == kHole) {
    next_[next_count_++] = t;
    return;
  }
  fills_.push_back({t, best});
  marks_[t] = kMarkFilled;
}

#if defined(__AVX512F__)
// crack() for every hole, sixteen pixels of a row a step away from the border (the per-hole
// branches mispredicted), with the same fills. The keys' depth halves are compared sixteen to a
// vector with crack()'s float compares: a hole key's depth bits are a NaN, which fails them, so a
// hole neighbour never counts. A fifth of the pixels are holes after a small turn (the splat's
// collisions), so the holes' marks, fills and leftovers are stored a vector at a time, and a
// row's fills are applied once the next row, the last to read its keys, is done (while they are
// still in cache).
void Reprojector::cracks16(int w, int h) {
  const __m512i hole = _mm512_set1_epi64(int64_t(kHole));
  const __m512 slack = _mm512_set1_ps(1.05f);
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i odd = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
  const auto scalar = [&](size_t t) {
    if (key_[t] == kHole) crack(uint32_t(t), w, h);
  };
  const size_t groups = size_t(w + 15) / 16;
  for (int b = 0; b < 2; ++b) {
    row_fill_[b].resize(groups * 16);
    row_found_[b].assign(groups * 2, 0);
  }
  // Row y's interior fills, from row_fill_[y & 1] where row_found_ says, once row y + 1 is done.
  const auto apply = [&](int y) {
    uint8_t* found = row_found_[y & 1].data();
    const uint64_t* fill = row_fill_[y & 1].data();
    const size_t row = size_t(y) * size_t(w);
    for (size_t g = 0; g < 2 * groups; ++g) {
      if (!found[g]) continue;
      _mm512_mask_storeu_epi64(&key_[row + 1 + 8 * g], __mmask8(found[g]), _mm512_loadu_si512(fill + 8 * g));
      found[g] = 0;
    }
  };
  for (int y = 0; y < h; ++y) {
    const size_t row = size_t(y) * size_t(w);
    if (y == 0 || y == h - 1) {
      for (int x = 0; x < w; ++x) scalar(row + size_t(x));
    } else {
      scalar(row);
      const size_t end = size_t(h) * size_t(w);
      uint8_t* found_row = row_found_[y & 1].data();
      // Locals: through the members, every store made the loop load the count and data pointers again.
      size_t left_count = next_count_;
      uint64_t* keys = key_.data();
      uint8_t* marks = marks_.data();
      uint32_t* next = next_.data();
      uint64_t* fill_row = row_fill_[y & 1].data();
      for (int x = 1; x < w - 1; x += 16) {
        const size_t t = row + size_t(x);
        // The next row is read only around holes (sparse masked loads the hardware prefetchers do
        // not follow) and was last touched by the splat: ask for it 64 pixels ahead.
        if (t + size_t(w) + 64 < end) __builtin_prefetch(&keys[t + size_t(w) + 64]);
        const __mmask16 lanes = __mmask16(w - 1 - x >= 16 ? 0xffffu : (1u << (w - 1 - x)) - 1u);
        const __mmask8 lanes_lo = __mmask8(lanes), lanes_hi = __mmask8(lanes >> 8);
        const __mmask16 holes = __mmask16(
            _mm512_mask_cmpeq_epu64_mask(lanes_lo, _mm512_maskz_loadu_epi64(lanes_lo, &keys[t]), hole) |
            _mm512_mask_cmpeq_epu64_mask(lanes_hi, _mm512_maskz_loadu_epi64(lanes_hi, &keys[t + 8]), hole) << 8);
        if (!holes) continue;
        const __mmask8 holes_lo = __mmask8(holes), holes_hi = __mmask8(holes >> 8);
        // The sixteen keys at offset `off` from the holes (kHole where none is loaded) and their depths.
        struct Keys {
          __m512i lo, hi;
          __m512 depth;
        };
        const auto keys_at = [&](ptrdiff_t off) {
          const uint64_t* at = &keys[size_t(ptrdiff_t(t) + off)];
          Keys k{_mm512_mask_loadu_epi64(hole, holes_lo, at), _mm512_mask_loadu_epi64(hole, holes_hi, at + 8), {}};
          k.depth = _mm512_castsi512_ps(_mm512_permutex2var_epi32(k.lo, odd, k.hi));
          return k;
        };
        __m512i best_depth = _mm512_setzero_si512(), best_lo = hole, best_hi = hole;
        __mmask16 found = 0;
        for (const auto& d : kOpposite) {
          const ptrdiff_t off = ptrdiff_t(d[1]) * w + d[0];
          const Keys p = keys_at(off), q = keys_at(-off);
          const __m512 dp = p.depth, dq = q.depth;
          // crack()'s max(dp, dq) <= min(dp, dq) * 1.05 for positive depths; false where either is a hole.
          const __mmask16 ok = _mm512_mask_cmp_ps_mask(holes, dp, _mm512_mul_ps(dq, slack), _CMP_LE_OQ) &
                               _mm512_cmp_ps_mask(dq, _mm512_mul_ps(dp, slack), _CMP_LE_OQ);
          // The farther of the pair (p on a tie), as crack(): positive depths order as their bits.
          const __m512i ip = _mm512_castps_si512(dp), iq = _mm512_castps_si512(dq);
          const __mmask16 take_p = _mm512_cmpge_epu32_mask(ip, iq);
          const __m512i f = _mm512_max_epu32(ip, iq);
          const __mmask16 better = ok & __mmask16(~found | _mm512_cmpgt_epu32_mask(f, best_depth));
          best_depth = _mm512_mask_mov_epi32(best_depth, better, f);
          // The whole keys (depth and source) by halves: gathering the sources at the end
          // measured no faster, and gathers are microcoded on some cores.
          const __mmask16 from_p = better & take_p, from_q = better & __mmask16(~take_p);
          best_lo = _mm512_mask_mov_epi64(_mm512_mask_mov_epi64(best_lo, __mmask8(from_p), p.lo), __mmask8(from_q), q.lo);
          best_hi = _mm512_mask_mov_epi64(_mm512_mask_mov_epi64(best_hi, __mmask8(from_p >> 8), p.hi),
                                          __mmask8(from_q >> 8), q.hi);
          found |= better;
        }
        const size_t g = size_t(x - 1) / 16;
        _mm512_storeu_si512(fill_row + 16 * g, best_lo);
        _mm512_storeu_si512(fill_row + 16 * g + 8, best_hi);
        const uint16_t found_bits = uint16_t(found);
        std::memcpy(found_row + 2 * g, &found_bits, sizeof found_bits);
        _mm_mask_storeu_epi8(&marks[t], found, _mm_set1_epi8(char(kMarkFilled)));
        const __mmask16 left = holes & __mmask16(~found);
        // Compressed in a register, stored whole (next_ has 16 spare): a compressing store to
        // memory is microcoded on some cores (Zen 4).
        _mm512_storeu_si512(&next[left_count], _mm512_maskz_compress_epi32(left, _mm512_add_epi32(lane, _mm512_set1_epi32(int(t)))));
        left_count += size_t(__builtin_popcount(left));
      }
      next_count_ = left_count;
      scalar(row + size_t(w) - 1);
    }
    if (y >= 2) apply(y - 1);  // row y - 1's keys are read by rows y - 2 to y only
  }
}
#endif

void Reprojector::land(size_t p, bool in, float px, float py, float depth, uint32_t kind, int w) {
  if (!in) return;
  const size_t t = size_t(int(py)) * size_t(w) + size_t(int(px));
  key_[t] = std::min(key_[t], make_key(depth, uint32_t(p)));
  moved_[p] = view_bits(px, py, kind);
}

void Reprojector::splat_one(const ViewMove& move, const SlotImage& from, size_t p, int w) {
  float px, py, d;
  if (from.engine_points && !from.marks[p]) {  // the engine's newest point, in world space
    const ScenePoint point = engine_point(from, p);
    const bool in = move.to(point, px, py, d);
    land(p, in, px, py, d, view_kind_of(point.object), w);
    return;
  }
  const ViewPoint& v = from.points[p];
  const bool in = move(v, uint32_t(p % size_t(w)), uint32_t(p / size_t(w)), px, py, d);
  land(p, in, px, py, d, view_kind(v.bits), w);
}

ReprojectStats Reprojector::run(const CameraBasis& before, const CameraBasis& after, const SlotImage& from,
                                const SlotImage& to, bool world_moves, int max_fill, EpochCensus* census) {
  const int w = from.width, h = from.height;
  const size_t n = from.pixels();
  // Where the time goes (bench reproject, bench engine): the clocks read between phases.
  times_ = {};
  PhaseClock clock(times_);
  // The keys and marks start as holes and moves; the last run's gather left them so (keys_clear_),
  // which saves the two arrays' fills here. The spare key past the image takes the vector
  // splats' lanes that land nowhere.
  if (!keys_clear_ || key_.size() != n + 1 || marks_.size() != n) {
    key_.assign(n + 1, kHole);
    marks_.assign(n, kMarkMoved);
  }
  key_[n] = kHole;
  keys_clear_ = false;
  // Forward splat: each pixel's point lands in one pixel; the nearest wins (the sky loses to any
  // surface, and between two sky points the first stays). Points lie on their pixel centre's ray
  // (trace_sample), so each pixel moves by its centre's motion. An unmarked pixel's point is the
  // engine's newest (world space, projected by splat_one); where each source landed is kept in
  // moved_ for the gather.
  const ViewMove move(before, after);
  if (moved_.size() < n) moved_.resize(n);
  size_t p0 = 0;
#if defined(__AVX512F__)
  if (vectorized_) p0 = splat16(move, from, w);
#elif defined(__AVX2__)
  if (vectorized_) p0 = splat8(move, from, w);
#endif
  for (size_t p = p0; p < n; ++p) splat_one(move, from, p, w);
  clock.lap(ReprojectTimes::splat);
  // Cracks first: a hole with landed neighbours of about one depth on opposite sides lies inside
  // a magnified surface, and takes the farther of such a pair.
  fills_.clear();
  if (next_.size() < n + 16) next_.resize(n + 16);  // holes left for the disocclusion search: next_[0, next_count_)
  next_count_ = 0;
#if defined(__AVX512F__)
  if (vectorized_ && w >= 3 && h >= 3) {
    cracks16(w, h);
  } else
#elif defined(__AVX2__)
  if (vectorized_ && w >= 3 && h >= 3) {
    cracks4(w, h);
  } else
#endif
  {
    for (size_t t = 0; t < n; ++t)
      if (key_[t] == kHole) crack(uint32_t(t), w, h);
  }
  for (const Fill& f : fills_) key_[f.pixel] = f.key;
  clock.lap(ReprojectTimes::cracks);
  // Disocclusions: what an object uncovers lies behind it, so each remaining hole takes the
  // farthest landed pixel within `max_fill` pixels; none there: it keeps its old content.
  fills_.clear();
  // The vector window is cheaper than the rows at any number of holes.
  const bool by_rows =
      search_ == Search::rows || (search_ == Search::automatic && !vector_window(max_fill) && next_count_ > n / 8);
  if (by_rows) {  // many holes (large steps: an edge band of new view)
    row_best_.resize(n);
    row_done_.assign(size_t(h), 0);
    prefix_.resize(size_t(w + 2 * max_fill));
    suffix_.resize(size_t(w + 2 * max_fill));
  }
  for (size_t i = 0; i < next_count_; ++i) {
    const uint32_t t = next_[i];
    const int x = int(t % uint32_t(w)), y = int(t / uint32_t(w));
    const uint32_t best = by_rows ? farthest_in_rows(x, y, w, h, max_fill) : farthest_in_window(x, y, w, h, max_fill);
    marks_[t] = kMarkDisoccluded;
    if (best != kNone) fills_.push_back({t, key_[best]});
  }
  for (const Fill& f : fills_) key_[f.pixel] = f.key;
  clock.lap(ReprojectTimes::disocclusions);
  return gather(from, to, world_moves, census, clock);
}

void PhaseClock::lap(ReprojectTimes::Phase phase) {
  const auto wall = std::chrono::steady_clock::now();
  const uint64_t cpu = thread_cpu_ns();
  times_.ms[phase] += std::chrono::duration<double, std::milli>(wall - wall_).count();
  times_.cpu_ms[phase] += double(cpu - cpu_ns_) * 1e-6;
  wall_ = wall;
  cpu_ns_ = cpu;
}

}  // namespace frameless
