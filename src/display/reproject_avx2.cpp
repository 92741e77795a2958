// Reprojection's splat, crack search and disocclusion window in AVX2, for cores without AVX-512 (the AMD EPYC 7xx3
// machines this project also runs on, where the scalar splat and crack search took 60 % of a
// change): the same operations as the scalar code, so the same image (tested).
#include <algorithm>
#include <cstring>
#include <limits>

#include "display/reproject.h"
#include "display/reproject_keys.h"

#if defined(__AVX2__) && !defined(__AVX512F__)
#include <immintrin.h>

namespace frameless {
using namespace reproject_keys;
namespace {

// Bit i set where byte i of the eight at `p` is zero (kMarkNone).
inline uint32_t zero_bytes(const uint8_t* p) {
  const __m128i v = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
  return uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_setzero_si128()))) & 0xffu;
}

}  // namespace

// land_engine16 eight points at a time: the batch's (at most eight), projected as Projector does
// and landed as land() lands them.
void Reprojector::land_engine8(const Projector& to, const EngineBatch& b, int w) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256i obj = _mm256_load_si256(reinterpret_cast<const __m256i*>(b.object));
  const __m256 sky = _mm256_castsi256_ps(_mm256_cmpeq_epi32(obj, _mm256_set1_epi32(int(kPointSky))));
  const __m256i none = _mm256_cmpeq_epi32(obj, _mm256_set1_epi32(int(kPointNone)));
  // object >= kPointDynamic (unsigned): the largest of the two is the object
  const __m256i moving = _mm256_cmpeq_epi32(_mm256_max_epu32(obj, _mm256_set1_epi32(int(kPointDynamic))), obj);
  // d = p - eye, the sky's p itself (a direction)
  const auto diff = [&](const float* c, float e) {
    const __m256 v = _mm256_load_ps(c);
    return _mm256_blendv_ps(_mm256_sub_ps(v, _mm256_set1_ps(e)), v, sky);
  };
  const __m256 dx = diff(b.x, to.eye.x), dy = diff(b.y, to.eye.y), dz = diff(b.z, to.eye.z);
  const auto dot = [&](const Vec3& a) {  // dot_exact(d, a)
    return _mm256_fmadd_ps(dx, _mm256_set1_ps(a.x),
                           _mm256_fmadd_ps(dy, _mm256_set1_ps(a.y), _mm256_mul_ps(dz, _mm256_set1_ps(a.z))));
  };
  const __m256 z = dot(to.w);
  const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), z);
  const __m256 sx = _mm256_fmadd_ps(dot(to.x), inv, _mm256_set1_ps(to.cx));
  const __m256 sy = _mm256_fnmadd_ps(dot(to.y), inv, _mm256_set1_ps(to.cy));
  __m256 in = _mm256_cmp_ps(z, zero, _CMP_GT_OQ);
  in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(sx, zero, _CMP_GE_OQ),
                                       _mm256_cmp_ps(sx, _mm256_set1_ps(to.width), _CMP_LT_OQ)));
  in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(sy, zero, _CMP_GE_OQ),
                                       _mm256_cmp_ps(sy, _mm256_set1_ps(to.height), _CMP_LT_OQ)));
  const uint32_t landed = uint32_t(_mm256_movemask_ps(_mm256_andnot_ps(_mm256_castsi256_ps(none), in))) &
                          ((1u << b.count) - 1u);
  if (!landed) return;
  // view_kind_of: static 2, sky 1, moving 3 (none never lands)
  __m256i kind = _mm256_blendv_epi8(_mm256_set1_epi32(int(kViewStatic)), _mm256_set1_epi32(int(kViewSky)),
                                    _mm256_castps_si256(sky));
  kind = _mm256_blendv_epi8(kind, _mm256_set1_epi32(int(kViewMoving)), moving);
  const __m256i ix = _mm256_cvttps_epi32(sx), iy = _mm256_cvttps_epi32(sy);
  const __m256 scale = _mm256_set1_ps(kViewFractionScale);
  const __m256i qx = _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_sub_ps(sx, _mm256_cvtepi32_ps(ix)), scale));
  const __m256i qy = _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_sub_ps(sy, _mm256_cvtepi32_ps(iy)), scale));
  alignas(32) uint32_t target[8], word[8], depth[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(target), _mm256_add_epi32(_mm256_mullo_epi32(iy, _mm256_set1_epi32(w)), ix));
  _mm256_store_si256(reinterpret_cast<__m256i*>(word),
                     _mm256_or_si256(_mm256_or_si256(qx, _mm256_slli_epi32(qy, kViewFractionBits)),
                                     _mm256_slli_epi32(kind, kViewKindShift)));
  _mm256_store_ps(reinterpret_cast<float*>(depth),
                  _mm256_blendv_ps(z, _mm256_set1_ps(std::numeric_limits<float>::infinity()), sky));
  land_lanes(landed, b, target, depth, word);
}

// splat16 eight pixels a step: two vectors of four view points split into depths and bits,
// moved with ViewMove's fused operations, then each landed point's key kept if nearer (a minimum:
// the order of the lanes does not matter); unmarked pixels go to splat_one.
size_t Reprojector::splat8(const ViewMove& mv, const SlotImage& from, int w) {
  if (w < 8) return 0;  // a step's pixels span at most two rows
  const size_t n = from.pixels() / 8 * 8;
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i fraction = _mm256_set1_epi32(int(kViewFractionMask)), width = _mm256_set1_epi32(w);
  const __m256 half = _mm256_set1_ps(0.5f), step = _mm256_set1_ps(kViewFractionStep);
  const __m256 zero = _mm256_setzero_ps(), scale = _mm256_set1_ps(kViewFractionScale);
  const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
  const __m256i sky = _mm256_set1_epi32(int(kViewSky));
  alignas(32) uint32_t target[8];
  alignas(32) uint64_t mine[8];
  EngineBatch batch;
  const __m256i spare = _mm256_set1_epi32(int(from.pixels()));  // key_[pixels]: written, never read
  uint32_t x0 = 0, y0 = 0;  // pixel p's column and row
  for (size_t p = 0; p < n; p += 8, x0 += 8) {
    if (x0 >= uint32_t(w)) x0 -= uint32_t(w), ++y0;
    uint32_t engine = 0;
    if (from.engine_points) {  // unmarked pixels show the engine's newest point (few while moving)
      // Scattered among the marked ones and last written by a render thread's core: asked for
      // 64 pixels ahead.
      if (p + 64 + 8 <= n)
        for (uint32_t m = zero_bytes(from.marks + p + 64); m; m &= m - 1u)
          __builtin_prefetch(from.engine_points + p + 64 + __builtin_ctz(m));
      engine = zero_bytes(from.marks + p);
    }
    const float* f = reinterpret_cast<const float*>(from.points + p);
    const __m256 a = _mm256_loadu_ps(f), b = _mm256_loadu_ps(f + 8);
    // Lanes 0, 1, 4, 5, 2, 3, 6, 7 of each shuffle; the 64-bit permute puts them in order.
    const __m256 depth = _mm256_castpd_ps(
        _mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))), _MM_SHUFFLE(3, 1, 2, 0)));
    const __m256i bits = _mm256_castpd_si256(
        _mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1))), _MM_SHUFFLE(3, 1, 2, 0)));
    const __m256i kind = _mm256_srli_epi32(bits, kViewKindShift);
    __m256i x = _mm256_add_epi32(_mm256_set1_epi32(int(x0)), lane);
    const __m256i wrap = _mm256_cmpgt_epi32(x, _mm256_set1_epi32(w - 1));
    x = _mm256_sub_epi32(x, _mm256_and_si256(wrap, width));
    const __m256i y = _mm256_sub_epi32(_mm256_set1_epi32(int(y0)), wrap);  // wrap lanes are -1
    // view_position
    const __m256 X = _mm256_fmadd_ps(_mm256_add_ps(_mm256_cvtepi32_ps(_mm256_and_si256(bits, fraction)), half), step,
                                     _mm256_cvtepi32_ps(x));
    const __m256 Y = _mm256_fmadd_ps(
        _mm256_add_ps(_mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(bits, kViewFractionBits), fraction)), half),
        step, _mm256_cvtepi32_ps(y));
    const __m256 is_sky = _mm256_castsi256_ps(_mm256_cmpeq_epi32(kind, sky));
    const auto axis = [&](int i) {
      const __m256 k = _mm256_fmadd_ps(_mm256_set1_ps(mv.k2[i]), Y,
                                       _mm256_fmadd_ps(_mm256_set1_ps(mv.k1[i]), X, _mm256_set1_ps(mv.k0[i])));
      return _mm256_blendv_ps(_mm256_fmadd_ps(depth, k, _mm256_set1_ps(mv.t[i])), k, is_sky);
    };
    const __m256 z = axis(0);
    const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), z);
    const __m256 sx = _mm256_fmadd_ps(axis(1), inv, _mm256_set1_ps(mv.to.cx));
    const __m256 sy = _mm256_fnmadd_ps(axis(2), inv, _mm256_set1_ps(mv.to.cy));
    __m256 in = _mm256_cmp_ps(z, zero, _CMP_GT_OQ);
    in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(sx, zero, _CMP_GE_OQ),
                                         _mm256_cmp_ps(sx, _mm256_set1_ps(mv.to.width), _CMP_LT_OQ)));
    in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(sy, zero, _CMP_GE_OQ),
                                         _mm256_cmp_ps(sy, _mm256_set1_ps(mv.to.height), _CMP_LT_OQ)));
    in = _mm256_andnot_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(kind, _mm256_setzero_si256())), in);
    const uint32_t landed = uint32_t(_mm256_movemask_ps(in)) & ~engine;
    if (landed) {
      const __m256i ix = _mm256_cvttps_epi32(sx), iy = _mm256_cvttps_epi32(sy);
      const __m256i store = _mm256_cmpgt_epi32(_mm256_and_si256(_mm256_set1_epi32(int(landed)),
                                                                _mm256_sllv_epi32(_mm256_set1_epi32(1), lane)),
                                               _mm256_setzero_si256());
      _mm256_store_si256(reinterpret_cast<__m256i*>(target),
                         _mm256_blendv_epi8(spare, _mm256_add_epi32(_mm256_mullo_epi32(iy, width), ix), store));
      const __m256i depths = _mm256_castps_si256(_mm256_blendv_ps(z, inf, is_sky));
      const __m256i source = _mm256_add_epi32(_mm256_set1_epi32(int(p)), lane);
      const auto keys = [](__m128i d, __m128i s) {
        return _mm256_or_si256(_mm256_slli_epi64(_mm256_cvtepu32_epi64(d), 32), _mm256_cvtepu32_epi64(s));
      };
      _mm256_store_si256(reinterpret_cast<__m256i*>(mine),
                         keys(_mm256_castsi256_si128(depths), _mm256_castsi256_si128(source)));
      _mm256_store_si256(reinterpret_cast<__m256i*>(mine + 4),
                         keys(_mm256_extracti128_si256(depths, 1), _mm256_extracti128_si256(source, 1)));
      // view_bits
      const __m256i qx = _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_sub_ps(sx, _mm256_cvtepi32_ps(ix)), scale));
      const __m256i qy = _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_sub_ps(sy, _mm256_cvtepi32_ps(iy)), scale));
      const __m256i word = _mm256_or_si256(_mm256_or_si256(qx, _mm256_slli_epi32(qy, kViewFractionBits)),
                                           _mm256_slli_epi32(kind, kViewKindShift));
      _mm256_maskstore_epi32(reinterpret_cast<int*>(moved_.data() + p), store, word);
      // As splat16: every lane's key, the lanes that landed nowhere into the spare key.
#pragma GCC unroll 8
      for (int i = 0; i < 8; ++i) {
        uint64_t& k = key_[target[i]];
        k = std::min(k, mine[i]);
      }
    }
    // Their world points read now, projected eight at a time (as splat16 does).
    for (uint32_t m = engine; m; m &= m - 1u) {
      const size_t q = p + __builtin_ctz(m);
      if (batch.add(engine_point(from, q), uint32_t(q)) == 8) land_engine8(mv.to, batch, w), batch.count = 0;
    }
  }
  if (batch.count) land_engine8(mv.to, batch, w);
  return n;
}

// crack() for every hole, four pixels of a row a step away from the border: the same float
// compares and depth-bit picks, so the same fills. A fifth of the pixels are holes after a small
// turn, found at random among the lanes, so nothing is decided lane by lane: a group's marks are
// one 4-byte store, its leftover holes one compressed store, and a row's fills are applied once
// the next row, the last to read its keys, is done (crack()'s fills, on the border, after the pass).
void Reprojector::cracks4(int w, int h) {
  const __m256i hole = _mm256_set1_epi64x(int64_t(kHole));
  const __m256 slack = _mm256_set1_ps(1.05f);
  const __m256 depth_half = _mm256_castsi256_ps(_mm256_set1_epi64x(int64_t(0xffffffff00000000ull)));
  const size_t end = size_t(h) * size_t(w);
  const size_t groups = size_t(w + 3) / 4;
  for (int b = 0; b < 2; ++b) {
    row_fill_[b].resize(groups * 4);
    row_found_[b].assign(groups, 0);
  }
  // By a group's mask of filled lanes: its four marks (little-endian bytes, lane 0 first), and
  // its lanes first to last, then zeros (not counted). Built once.
  struct Tables {
    uint32_t marks[16];
    alignas(16) int32_t compress[16][4];
  };
  static const Tables tables = [] {
    Tables t{};
    for (uint32_t m = 0; m < 16; ++m) {
      int k = 0;
      for (int i = 0; i < 4; ++i) {
        t.marks[m] |= uint32_t(m >> i & 1u ? kMarkFilled : kMarkMoved) << (8 * i);
        if (m >> i & 1u) t.compress[m][k++] = i;
      }
    }
    return t;
  }();
  const auto scalar = [&](size_t t) {
    if (key_[t] == kHole) crack(uint32_t(t), w, h);
  };
  // Row y's interior fills, from row_fill_[y & 1] where row_found_ says.
  const auto apply = [&](int y) {
    uint8_t* found = row_found_[y & 1].data();
    const uint64_t* fill = row_fill_[y & 1].data();
    const size_t row = size_t(y) * size_t(w);
    const __m256i lane_bit = _mm256_setr_epi64x(1, 2, 4, 8);
    for (size_t g = 0; g < groups; ++g) {
      if (!found[g]) continue;
      const __m256i lanes = _mm256_cmpeq_epi64(_mm256_and_si256(_mm256_set1_epi64x(found[g]), lane_bit), lane_bit);
      _mm256_maskstore_epi64(reinterpret_cast<long long*>(&key_[row + 1 + 4 * g]), lanes,
                             _mm256_loadu_si256(reinterpret_cast<const __m256i*>(fill + 4 * g)));
      found[g] = 0;
    }
  };
  for (int y = 0; y < h; ++y) {
    const size_t row = size_t(y) * size_t(w);
    if (y == 0 || y == h - 1) {  // the border: crack() alone
      for (int x = 0; x < w; ++x) scalar(row + size_t(x));
      if (y == h - 1 && y >= 2) apply(y - 1);
      continue;
    }
    scalar(row);
    // Locals: through the members, every store made the loop load the count and data pointers again.
    const uint64_t* keys = key_.data();
    uint8_t* marks = marks_.data();
    uint32_t* next = next_.data();
    size_t left_count = next_count_;
    uint64_t* fill_row = row_fill_[y & 1].data();
    uint8_t* found_row = row_found_[y & 1].data();
    int x = 1;
    for (; x + 4 <= w - 1; x += 4) {
      const size_t t = row + size_t(x);
      // The next row is read only around holes and was last touched by the splat: ask for it
      // 64 pixels ahead.
      if (t + size_t(w) + 64 < end) __builtin_prefetch(&keys[t + size_t(w) + 64]);
      const __m256i holes = _mm256_cmpeq_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(&keys[t])), hole);
      if (_mm256_testz_si256(holes, holes)) continue;
      // Each lane's answers live in bit 63 (what blendv_pd and movemask_pd read): the compares
      // run on the keys in place, their depth halves being the odd floats, so no shuffles.
      __m256i best = hole, found = _mm256_setzero_si256();
      for (const auto& d : kOpposite) {
        const ptrdiff_t off = ptrdiff_t(d[1]) * w + d[0];
        const __m256i kp = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&keys[size_t(ptrdiff_t(t) + off)]));
        const __m256i kq = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&keys[size_t(ptrdiff_t(t) - off)]));
        // The depths with the sources zeroed (a source's bits are a subnormal float, whose
        // multiply is slow on some cores); a hole's depth is a NaN, which fails every compare.
        const __m256 dp = _mm256_and_ps(_mm256_castsi256_ps(kp), depth_half);
        const __m256 dq = _mm256_and_ps(_mm256_castsi256_ps(kq), depth_half);
        // crack()'s max(dp, dq) <= min(dp, dq) * 1.05 for positive depths: not an edge between two surfaces.
        const __m256 near = _mm256_and_ps(_mm256_cmp_ps(dp, _mm256_mul_ps(dq, slack), _CMP_LE_OQ),
                                          _mm256_cmp_ps(dq, _mm256_mul_ps(dp, slack), _CMP_LE_OQ));
        const __m256i ok = _mm256_and_si256(_mm256_castps_si256(near), holes);
        const __m256i fill = _mm256_castpd_si256(_mm256_blendv_pd(
            _mm256_castsi256_pd(kq), _mm256_castsi256_pd(kp), _mm256_castps_pd(_mm256_cmp_ps(dp, dq, _CMP_GE_OQ))));
        const __m256i farther = _mm256_cmpgt_epi64(_mm256_srli_epi64(fill, 32), _mm256_srli_epi64(best, 32));
        // Taken where none was found yet or this pair's fill is farther.
        const __m256i better = _mm256_andnot_si256(_mm256_andnot_si256(farther, found), ok);
        best = _mm256_castpd_si256(_mm256_blendv_pd(_mm256_castsi256_pd(best), _mm256_castsi256_pd(fill), _mm256_castsi256_pd(better)));
        found = _mm256_or_si256(found, better);
      }
      const uint32_t hole_lanes = uint32_t(_mm256_movemask_pd(_mm256_castsi256_pd(holes)));
      const uint32_t found_lanes = uint32_t(_mm256_movemask_pd(_mm256_castsi256_pd(found)));
      const size_t g = size_t(x - 1) / 4;
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(fill_row + 4 * g), best);
      found_row[g] = uint8_t(found_lanes);
      std::memcpy(&marks[t], &tables.marks[found_lanes], 4);
      // The holes left for the disocclusion search, compressed in a register and stored whole
      // (next_ has 8 spare).
      const uint32_t left = hole_lanes & ~found_lanes;
      const __m128i at = _mm_add_epi32(_mm_setr_epi32(0, 1, 2, 3), _mm_set1_epi32(int(t)));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(&next[left_count]),
                       _mm_castps_si128(_mm_permutevar_ps(_mm_castsi128_ps(at), _mm_load_si128(reinterpret_cast<const __m128i*>(tables.compress[left])))));
      left_count += size_t(__builtin_popcount(left));
    }
    next_count_ = left_count;
    for (; x < w; ++x) scalar(row + size_t(x));
    if (y >= 2) apply(y - 1);  // row y - 1's keys are read by rows y - 2 to y only
  }
}

// farthest_in_window for r <= 3: a window row (at most 7 keys) in two vectors, its landed depths
// packed into one vector of eight, their maximum, and its first lane: the scalar search's pick
// (rows in pixel order, a strictly farther depth across rows, the lower pixel on a tie).
uint32_t Reprojector::farthest_in_window4(int x, int y, int w, int h, int r) const {
  const int x0 = std::max(0, x - r), x1 = std::min(w - 1, x + r);
  const __m256i count = _mm256_set1_epi64x(x1 - x0 + 1);
  const __m256i lo_lanes = _mm256_cmpgt_epi64(count, _mm256_setr_epi64x(0, 1, 2, 3));
  const __m256i hi_lanes = _mm256_cmpgt_epi64(count, _mm256_setr_epi64x(4, 5, 6, 7));
  const __m256i hole = _mm256_set1_epi64x(int64_t(kHole));
  const __m256i low = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);  // a 64-bit lane's low half
  uint32_t best = kNone, best_depth = 0;
  for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy) {
    const size_t base = size_t(yy) * size_t(w) + size_t(x0);
    const long long* row = reinterpret_cast<const long long*>(&key_[base]);
    const __m256i lo = _mm256_maskload_epi64(row, lo_lanes), hi = _mm256_maskload_epi64(row + 4, hi_lanes);
    // Depth bits of landed lanes; 0 elsewhere (a landed depth is positive).
    const __m256i lo_depth = _mm256_and_si256(_mm256_srli_epi64(lo, 32), _mm256_andnot_si256(_mm256_cmpeq_epi64(lo, hole), lo_lanes));
    const __m256i hi_depth = _mm256_and_si256(_mm256_srli_epi64(hi, 32), _mm256_andnot_si256(_mm256_cmpeq_epi64(hi, hole), hi_lanes));
    const __m256i depth = _mm256_inserti128_si256(
        _mm256_castsi128_si256(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(lo_depth, low))),
        _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(hi_depth, low)), 1);
    __m128i m = _mm_max_epu32(_mm256_castsi256_si128(depth), _mm256_extracti128_si256(depth, 1));
    m = _mm_max_epu32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    m = _mm_max_epu32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1)));
    const uint32_t d = uint32_t(_mm_cvtsi128_si32(m));
    if (d == 0 || (best != kNone && d <= best_depth)) continue;
    const uint32_t at = uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(depth, _mm256_set1_epi32(int(d))))));
    best = uint32_t(base) + uint32_t(__builtin_ctz(at));
    best_depth = d;
  }
  return best;
}

}  // namespace frameless
#endif
