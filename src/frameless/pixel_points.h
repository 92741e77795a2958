// What reprojection needs of each pixel's newest update (the render cache): its primary hit in
// world space and what it hit, kept beside the states by pixel index like the levels. Written by
// the render thread that owns the pixel inside its publish, read by the display thread with
// relaxed atomics under the point's own sequence lock (race-free under ThreadSanitizer, and never
// a mix of two updates). 32 bytes per pixel.
#pragma once
#include <atomic>
#include <cstdint>

#include "core/shading/render_sample.h"
#include "frameless/pixel_state.h"

namespace frameless {

struct alignas(32) PixelPoint {
  std::atomic<float> p[3] = {0.0f, 0.0f, 0.0f};  // world position (a direction for kPointSky)
  std::atomic<uint32_t> object{kPointNone};      // SampleResult::object
  // The point's own sequence lock, odd while its owner writes it: the display reads a point whole
  // without touching the pixel's state (the splat reads many points, in pixel order).
  std::atomic<uint32_t> seq{0};
  uint32_t unused[3] = {0, 0, 0};
};
static_assert(sizeof(PixelPoint) == 32, "two pixels' points per cache line");

// A plain copy of one pixel's point.
struct ScenePoint {
  Vec3 p{0.0f};
  uint32_t object = kPointNone;
};
static_assert(sizeof(ScenePoint) == 16);

// Render thread, inside the publish (before the closing sequence store), under the point's own
// sequence lock too.
inline void store_point(PixelPoint& slot, const SampleResult& r) {
  write_locked(slot.seq, [&] {
    for (int c = 0; c < 3; ++c) slot.p[c].store(r.position[c], std::memory_order_relaxed);
    slot.object.store(r.object, std::memory_order_relaxed);
  });
}

// Display thread: the pixel's newest point, whole (all of it from one update), read under its
// own sequence lock. False while the owner keeps rewriting it.
inline bool read_point(const PixelPoint& slot, ScenePoint& out, int max_tries = 16) {
  return read_locked(slot.seq, [&] {
    for (int c = 0; c < 3; ++c) out.p[c] = slot.p[c].load(std::memory_order_relaxed);
    out.object = slot.object.load(std::memory_order_relaxed);
  }, nullptr, max_tries);
}

// Display thread: the point of the update with state sequence number `seq`, read inside the
// state's sequence lock (the owner stores the point inside its publish). False if that update
// has been replaced since, or while the owner keeps writing.
inline bool read_point_of(const PixelState& state, uint32_t seq, const PixelPoint& slot, ScenePoint& out) {
  if (state.seq.load(std::memory_order_acquire) != seq) return false;
  if (!read_point(slot, out)) return false;
  std::atomic_thread_fence(std::memory_order_acquire);
  return state.seq.load(std::memory_order_relaxed) == seq;
}

}  // namespace frameless
