// What reprojection needs of each pixel's newest update (the render cache): its primary hit in
// world space and what it hit, kept beside the states by pixel index like the levels. Written by
// the render thread that owns the pixel inside its publish, read by the display thread with
// relaxed atomics (race-free under ThreadSanitizer). 16 bytes per pixel.
#pragma once
#include <atomic>
#include <cstdint>

#include "core/render_sample.h"
#include "frameless/pixel_state.h"

namespace frameless {

struct alignas(16) PixelPoint {
  std::atomic<float> p[3] = {0.0f, 0.0f, 0.0f};  // world position (a direction for kPointSky)
  std::atomic<uint32_t> object{kPointNone};      // SampleResult::object
};
static_assert(sizeof(PixelPoint) == 16, "four pixels' points per cache line");

// A plain copy of one pixel's point.
struct ScenePoint {
  Vec3 p{0.0f};
  uint32_t object = kPointNone;
};
static_assert(sizeof(ScenePoint) == 16);

// Render thread, inside the publish (before the closing sequence store).
inline void store_point(PixelPoint& slot, const SampleResult& r) {
  for (int c = 0; c < 3; ++c) slot.p[c].store(r.position[c], std::memory_order_relaxed);
  slot.object.store(r.object, std::memory_order_relaxed);
}

// Display thread: the point of the update it just read, or a newer one's. Its components may
// come from two updates; read_point() rules that out.
inline ScenePoint load_point(const PixelPoint& slot) {
  ScenePoint s;
  for (int c = 0; c < 3; ++c) s.p[c] = slot.p[c].load(std::memory_order_relaxed);
  s.object = slot.object.load(std::memory_order_relaxed);
  return s;
}

// Display thread: the point of the pixel's newest update, read inside its state's sequence lock
// as read_pixel() reads the state (the owner stores the point inside its publish), so every
// component comes from one update (whose sequence number goes to *seq). False while the owner
// keeps rewriting it.
inline bool read_point(const PixelState& state, const PixelPoint& slot, ScenePoint& out,
                       uint32_t* seq = nullptr, int max_tries = 16) {
  for (int i = 0; i < max_tries; ++i) {
    const uint32_t s0 = state.seq.load(std::memory_order_acquire);
    if (s0 & 1u) continue;
    out = load_point(slot);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (state.seq.load(std::memory_order_relaxed) == s0) {
      if (seq) *seq = s0;
      return true;
    }
  }
  return false;
}

}  // namespace frameless
