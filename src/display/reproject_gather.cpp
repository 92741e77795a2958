// Reprojection's gather (the last step of Reprojector::run): from the landed keys, each pixel's
// new point, mark and source, then the pixels themselves. Moved content keeps its exact point:
// snapping it to the pixel centre made the image drift by up to half a pixel per reprojection (a
// random walk; worse error in bench motion although fewer holes). The engine's sequence numbers
// stay with the slots (the display keeps them apart from the pixels).
#include <chrono>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif
#include <cstring>

#include "display/reproject.h"
#include "display/reproject_keys.h"

namespace frameless {
using namespace reproject_keys;

namespace {

// Asks for the source of the pixel kSourceAhead on: the sources run as a stream shifted by the
// move, one of the pass's seven, which the hardware prefetchers lose (the pass took twice as
// long).
constexpr size_t kSourceAhead = 128;

#if defined(__AVX512F__)
// The four 16-byte quarters of v with streaming stores (the points are only 16-byte aligned).
inline void stream_quarters(__m128i* o, __m512i v) {
  _mm_stream_si128(o, _mm512_castsi512_si128(v));
  _mm_stream_si128(o + 1, _mm512_extracti32x4_epi32(v, 1));
  _mm_stream_si128(o + 2, _mm512_extracti32x4_epi32(v, 2));
  _mm_stream_si128(o + 3, _mm512_extracti32x4_epi32(v, 3));
}
#endif

}  // namespace

#if defined(__AVX512F__)
// The pass by pixel 16 pixels a step, the same values as the scalar place() of each: keys split
// into sources and depth bits, holes and marks decided by masks, the landed words and source
// slots gathered, points interleaved again. Adds the marks' counts (moved, filled, disoccluded,
// stale) to `count`; returns the pixels done.
size_t Reprojector::places16(const SlotImage& from, const SlotImage& to, bool world_moves, size_t count[4]) {
  const size_t n = from.pixels(), steps = n / 16 * 16;
  const __m512i even = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
  const __m512i odd = _mm512_add_epi32(even, _mm512_set1_epi32(1));
  const __m512i first = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
  const __m512i second = _mm512_add_epi32(first, _mm512_set1_epi32(8));
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i hole = _mm512_set1_epi64(int64_t(kHole));
  const __m512i unknown = _mm512_set1_epi32(kMarkDisoccluded | kMarkUnknown);
  const __m512i copied = _mm512_set1_epi32(kMarkFilled | kMarkDisoccluded);
  const __m512i kind = _mm512_set1_epi32(int(~0u << kViewKindShift)), centre = _mm512_set1_epi32(int(kViewCentre));
  const __m512i moving = _mm512_set1_epi32(int(kViewMoving)), stale = _mm512_set1_epi32(kMarkStale);
  const __m512i bit[4] = {_mm512_set1_epi32(kMarkMoved), _mm512_set1_epi32(kMarkFilled),
                          _mm512_set1_epi32(kMarkDisoccluded), stale};
  // Locals: through the members, every store would make the loop load the data pointers again.
  uint64_t* keys = key_.data();
  uint8_t* marks = marks_.data();
  const uint32_t* moved = moved_.data();
  const uint32_t* slot_of = from.slot_of;
  const __m128i moved_marks = _mm_set1_epi8(char(kMarkMoved));
  uint32_t* source_slot = source_slot_.data();
  uint8_t* out_marks = to.marks;
  int32_t* out_points = reinterpret_cast<int32_t*>(to.points);
  // The points with streaming stores, as the pass by slot writes the pixels (gather): the next
  // change reads them, by when the render threads have pushed their lines out of the caches.
  const bool stream_points = (reinterpret_cast<uintptr_t>(to.points) & 15) == 0;
  for (size_t t = 0; t < steps; t += 16) {
    if (t + kSourceAhead + 16 <= n) {  // the sources of a step lie on a line or two
      for (const size_t at : {t + kSourceAhead, t + kSourceAhead + 15}) {
        const uint32_t ahead = uint32_t(keys[at]);
        if (ahead < n) {
          __builtin_prefetch(moved + ahead);
          if (slot_of) __builtin_prefetch(slot_of + ahead);
        }
      }
    }
    const __m512i k0 = _mm512_loadu_si512(keys + t), k1 = _mm512_loadu_si512(keys + t + 8);
    const __mmask16 is_hole = __mmask16(_mm512_cmpeq_epu64_mask(k0, hole) | _mm512_cmpeq_epu64_mask(k1, hole) << 8);
    const __m512i source = _mm512_mask_add_epi32(_mm512_permutex2var_epi32(k0, even, k1), is_hole,
                                                 _mm512_set1_epi32(int(t)), lane);
    __m512i mark = _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(marks + t)));
    // Read for the last time: cleared for the next run here, while in cache (keys_clear_).
    _mm512_storeu_si512(keys + t, hole);
    _mm512_storeu_si512(keys + t + 8, hole);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(marks + t), moved_marks);
    mark = _mm512_mask_mov_epi32(mark, is_hole, unknown);
    const __mmask16 known = _mm512_testn_epi32_mask(mark, _mm512_set1_epi32(kMarkUnknown));
    const __m512i landed = _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), known, source, moved, 4);
    // A copy of a neighbour's content: this pixel's centre, the landed point's kind.
    __m512i bits = _mm512_mask_or_epi32(landed, _mm512_test_epi32_mask(mark, copied), centre,
                                        _mm512_and_si512(landed, kind));
    bits = _mm512_maskz_mov_epi32(known, bits);
    const __m512i depth = _mm512_maskz_mov_epi32(known, _mm512_permutex2var_epi32(k0, odd, k1));
    if (world_moves)
      mark = _mm512_mask_or_epi32(mark, _mm512_cmpeq_epi32_mask(_mm512_srli_epi32(bits, kViewKindShift), moving),
                                  mark, stale);
    const __m512i p0 = _mm512_permutex2var_epi32(depth, first, bits), p1 = _mm512_permutex2var_epi32(depth, second, bits);
    if (stream_points) {
      __m128i* o = reinterpret_cast<__m128i*>(out_points + 2 * t);
      stream_quarters(o, p0);
      stream_quarters(o + 4, p1);
    } else {
      _mm512_storeu_si512(out_points + 2 * t, p0);
      _mm512_storeu_si512(out_points + 2 * t + 16, p1);
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out_marks + t), _mm512_cvtepi32_epi8(mark));
    for (int b = 0; b < 4; ++b) count[b] += size_t(__builtin_popcount(_mm512_test_epi32_mask(mark, bit[b])));
    _mm512_storeu_si512(source_slot + t, slot_of ? _mm512_i32gather_epi32(source, slot_of, 4) : source);
  }
  return steps;
}
#elif defined(__AVX2__)
// places16 eight pixels a step, for cores without AVX-512: the same values as place().
size_t Reprojector::places8(const SlotImage& from, const SlotImage& to, bool world_moves, size_t count[4]) {
  const size_t n = from.pixels(), steps = n / 8 * 8;
  const __m256i split = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);  // a key's halves apart
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), ones = _mm256_set1_epi32(-1);
  const __m256i zero = _mm256_setzero_si256();
  const __m256i unknown = _mm256_set1_epi32(kMarkDisoccluded | kMarkUnknown);
  const __m256i unknown_bit = _mm256_set1_epi32(kMarkUnknown);
  const __m256i copied = _mm256_set1_epi32(kMarkFilled | kMarkDisoccluded);
  const __m256i kind = _mm256_set1_epi32(int(~0u << kViewKindShift)), centre = _mm256_set1_epi32(int(kViewCentre));
  const __m256i moving = _mm256_set1_epi32(int(kViewMoving)), stale = _mm256_set1_epi32(kMarkStale);
  const __m256i bit[4] = {_mm256_set1_epi32(kMarkMoved), _mm256_set1_epi32(kMarkFilled),
                          _mm256_set1_epi32(kMarkDisoccluded), stale};
  uint64_t* keys = key_.data();
  uint8_t* marks = marks_.data();
  const int* moved = reinterpret_cast<const int*>(moved_.data());
  const int* slot_of = reinterpret_cast<const int*>(from.slot_of);
  uint32_t* source_slot = source_slot_.data();
  uint8_t* out_marks = to.marks;
  int32_t* out_points = reinterpret_cast<int32_t*>(to.points);
  const bool stream_points = (reinterpret_cast<uintptr_t>(to.points) & 15) == 0;
  for (size_t t = 0; t < steps; t += 8) {
    if (t + kSourceAhead + 8 <= n) {
      const uint32_t ahead = uint32_t(keys[t + kSourceAhead]);
      if (ahead < n) {
        __builtin_prefetch(moved + ahead);
        if (slot_of) __builtin_prefetch(slot_of + ahead);
      }
    }
    const __m256i a = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(keys + t)), split);
    const __m256i b = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(keys + t + 4)), split);
    __m256i source = _mm256_permute2x128_si256(a, b, 0x20);
    const __m256i depth_bits = _mm256_permute2x128_si256(a, b, 0x31);
    const __m256i is_hole = _mm256_and_si256(_mm256_cmpeq_epi32(source, ones), _mm256_cmpeq_epi32(depth_bits, ones));
    source = _mm256_blendv_epi8(source, _mm256_add_epi32(_mm256_set1_epi32(int(t)), lane), is_hole);
    __m256i mark = _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(marks + t)));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(keys + t), ones);  // cleared for the next run (keys_clear_)
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(keys + t + 4), ones);
    std::memset(marks + t, kMarkMoved, 8);
    mark = _mm256_blendv_epi8(mark, unknown, is_hole);
    const __m256i known = _mm256_cmpeq_epi32(_mm256_and_si256(mark, unknown_bit), zero);
    const __m256i landed = _mm256_mask_i32gather_epi32(zero, moved, source, known, 4);
    const __m256i copy = _mm256_xor_si256(_mm256_cmpeq_epi32(_mm256_and_si256(mark, copied), zero), ones);
    __m256i bits = _mm256_blendv_epi8(landed, _mm256_or_si256(centre, _mm256_and_si256(landed, kind)), copy);
    bits = _mm256_and_si256(bits, known);
    const __m256i depth = _mm256_and_si256(depth_bits, known);
    if (world_moves)
      mark = _mm256_or_si256(mark, _mm256_and_si256(_mm256_cmpeq_epi32(_mm256_srli_epi32(bits, kViewKindShift), moving), stale));
    const __m256i lo = _mm256_unpacklo_epi32(depth, bits), hi = _mm256_unpackhi_epi32(depth, bits);
    const __m256i p0 = _mm256_permute2x128_si256(lo, hi, 0x20), p1 = _mm256_permute2x128_si256(lo, hi, 0x31);
    if (stream_points) {  // as places16
      __m128i* o = reinterpret_cast<__m128i*>(out_points + 2 * t);
      _mm_stream_si128(o, _mm256_castsi256_si128(p0));
      _mm_stream_si128(o + 1, _mm256_extracti128_si256(p0, 1));
      _mm_stream_si128(o + 2, _mm256_castsi256_si128(p1));
      _mm_stream_si128(o + 3, _mm256_extracti128_si256(p1, 1));
    } else {
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out_points + 2 * t), p0);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out_points + 2 * t + 8), p1);
    }
    const __m256i bytes = _mm256_packus_epi16(_mm256_packus_epi32(mark, mark), zero);  // marks 0-3 | 4-7 per half
    const uint64_t packed = uint32_t(_mm_cvtsi128_si32(_mm256_castsi256_si128(bytes))) |
                            uint64_t(uint32_t(_mm_cvtsi128_si32(_mm256_extracti128_si256(bytes, 1)))) << 32;
    std::memcpy(out_marks + t, &packed, sizeof packed);
    for (int k = 0; k < 4; ++k)
      count[k] += size_t(__builtin_popcount(
          uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(mark, bit[k]), bit[k]))))));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(source_slot + t),
                        slot_of ? _mm256_i32gather_epi32(slot_of, source, 4) : source);
  }
  return steps;
}
#endif

ReprojectStats Reprojector::gather(const SlotImage& from, const SlotImage& to, bool world_moves,
                                   EpochCensus* census, PhaseClock& clock) {
  const size_t n = from.pixels();
  // Four histograms, by pixel index: one counter bumped pixel after pixel would wait on its own
  // store each time.
  size_t by_mark[4][256] = {};
  // What pixel t shows: the slot of `from` its content comes from; its point and mark are written.
  // Forced inline: clang kept it a call per pixel, and the pass took 1.5-2 times as long.
  const auto place = [&](size_t t) __attribute__((always_inline)) {
    const uint64_t key = key_[t];
    uint32_t source = uint32_t(key);
    uint8_t mark = marks_[t];
    key_[t] = kHole;  // read for the last time: cleared for the next run (keys_clear_)
    marks_[t] = kMarkMoved;
    if (key == kHole) {  // nothing reached it: its old content, marked as a guess
      source = uint32_t(t);
      mark = kMarkDisoccluded | kMarkUnknown;
    }
    // Moved content keeps where its point landed (the splat's moved_); a copy of a neighbour's
    // content gets its own point, at this pixel's centre at that depth: a copy of the
    // neighbour's point would collide with it next time and open the hole again. Old content
    // under a hole keeps no point (it is a guess the next sample replaces).
    ViewPoint point;
    if (!(mark & kMarkUnknown)) {
      const uint32_t landed = moved_[source];
      point.depth = key_depth(key);
      point.bits = mark & (kMarkFilled | kMarkDisoccluded) ? kViewCentre | (landed & ~0u << kViewKindShift) : landed;
    }
    if (world_moves && view_kind(point.bits) == kViewMoving) mark |= kMarkStale;
    to.points[t] = point;
    to.marks[t] = mark;
    ++by_mark[t & 3][mark];
    return from.slot(source);
  };
  // A macro: GCC drops a call whose only effect is a prefetch as pure.
  const uint64_t* keys = key_.data();
#define FRAMELESS_FETCH_SOURCE(t)                                                          \
  if ((t) + kSourceAhead < n) {                                                            \
    const uint32_t ahead = uint32_t(keys[(t) + kSourceAhead]);                             \
    if (ahead < n) { /* else a hole */                                                     \
      __builtin_prefetch(moved_.data() + ahead);                                           \
      __builtin_prefetch(from.slot_of ? static_cast<const void*>(from.slot_of + ahead) : from.px + ahead); \
    }                                                                                      \
  }
  // The census counts by epoch in 64 buckets (e mod 64) on the stack, four copies by index so
  // that neighbours of one epoch do not wait on each other's increment, and adds each bucket once:
  // a moving display's neighbours show epochs at random (the threads' pixels are shuffled), so
  // counting runs of one epoch mispredicted at most pixels. A bucket meeting another epoch (64
  // changes apart: rare) is added first.
  constexpr uint32_t kBuckets = 64;
  uint32_t bucket_epoch[kBuckets] = {}, bucket_count[4][kBuckets] = {};
  const auto flush = [&](uint32_t b) {
    const uint32_t c = bucket_count[0][b] + bucket_count[1][b] + bucket_count[2][b] + bucket_count[3][b];
    if (c) census->add(bucket_epoch[b], c);
    bucket_count[0][b] = bucket_count[1][b] = bucket_count[2][b] = bucket_count[3][b] = 0;
  };
  const auto count_epoch = [&](uint32_t e, size_t i) __attribute__((always_inline)) {
    if (!census) return;
    const uint32_t b = e % kBuckets;
    if (bucket_epoch[b] != e) {
      flush(b);
      bucket_epoch[b] = e;
    }
    ++bucket_count[i & 3][b];
  };
  size_t counted[4] = {};  // the vector pass's marks: moved, filled, disoccluded, stale
  if (!to.pixel_of) {
    for (size_t t = 0; t < n; ++t) {  // slot = pixel: every array streams
      FRAMELESS_FETCH_SOURCE(t)
      to.px[t] = from.px[place(t)];
      count_epoch(to.px[t].epoch, t);
    }
    keys_clear_ = true;
    clock.lap(ReprojectTimes::pixel_pass);
  } else {
    // Two passes: points and marks by pixel, then the pixels by slot. One walk doing both (either
    // order, even along the display's Hilbert curve) loses the hardware prefetchers: it mixes
    // pixel-indexed and slot-indexed arrays (benchmarks.md, sections 19 and 23).
    source_slot_.resize(n);
    size_t t0 = 0;
#if defined(__AVX512F__)
    if (vectorized_) t0 = places16(from, to, world_moves, counted);
#elif defined(__AVX2__)
    if (vectorized_) t0 = places8(from, to, world_moves, counted);
#endif
    for (size_t t = t0; t < n; ++t) {
      FRAMELESS_FETCH_SOURCE(t)
      source_slot_[t] = place(t);
    }
    keys_clear_ = true;
    clock.lap(ReprojectTimes::pixel_pass);
    // Slots stream; the source slot of the pixel kAhead slots on is fetched early, and its
    // content kAhead / 2 slots on.
    constexpr size_t kAhead = 256;
    const uint32_t* pixel_of = to.pixel_of;
    // Written with streaming stores, which skip reading the destination's lines first: beside
    // the render threads those lines have left the caches by the next change, and the reads
    // cost an eighth of the pass (benchmarks.md, section 36). They need 16-byte alignment.
    const bool stream = (reinterpret_cast<uintptr_t>(to.px) & 15) == 0;
    static_assert(offsetof(DisplayPixel, epoch) == 12, "the epoch is a pixel's last 4 bytes");
    for (size_t ts = 0; ts < n; ++ts) {
      if (ts + kAhead < n) __builtin_prefetch(&source_slot_[pixel_of[ts + kAhead]]);
      if (ts + kAhead / 2 < n) __builtin_prefetch(&from.px[source_slot_[pixel_of[ts + kAhead / 2]]]);
#if defined(__SSE2__)
      if (stream) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&from.px[source_slot_[pixel_of[ts]]]));
        _mm_stream_si128(reinterpret_cast<__m128i*>(&to.px[ts]), v);
        count_epoch(uint32_t(_mm_cvtsi128_si32(_mm_srli_si128(v, 12))), ts);  // the epoch, the last 4 bytes
        continue;
      }
#endif
      to.px[ts] = from.px[source_slot_[pixel_of[ts]]];
      count_epoch(to.px[ts].epoch, ts);
    }
#if defined(__SSE2__)
    _mm_sfence();  // the streaming stores (these and the points') ordered before the image is handed on
#endif
    clock.lap(ReprojectTimes::slot_pass);
  }
#undef FRAMELESS_FETCH_SOURCE
  if (census)
    for (uint32_t b = 0; b < kBuckets; ++b) flush(b);
  ReprojectStats stats;
  stats.moved = counted[0];
  stats.filled = counted[1];
  stats.disoccluded = counted[2];
  stats.stale = counted[3];
  for (int m = 0; m < 256; ++m) {
    const size_t c = by_mark[0][m] + by_mark[1][m] + by_mark[2][m] + by_mark[3][m];
    stats.moved += (m & kMarkMoved) ? c : 0;
    stats.filled += (m & kMarkFilled) ? c : 0;
    stats.disoccluded += (m & kMarkDisoccluded) ? c : 0;
    stats.stale += (m & kMarkStale) ? c : 0;
  }
  return stats;
}

}  // namespace frameless
