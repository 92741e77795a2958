// The reflection depth view's engine side (seed figure 1d): the deepest reflection/refraction
// level of each pixel's newest update, kept in Engine::Impl::levels by pixel index because
// PixelState fills its cache line. Written by the render thread that owns the pixel, read by the
// display thread without a lock (relaxed atomics: race-free under ThreadSanitizer).
#pragma once
#include <atomic>
#include <cstdint>

#include "frameless/engine_impl.h"

namespace frameless {

// Render thread, in update_pixel before the closing sequence store: then a display that reads
// the published state also sees these levels or newer ones. `levels` is the maximum
// SampleResult::levels of the update's valid samples; `frame` (conventional mode, else null)
// carries it with the frame's snapshot.
inline void store_levels(Engine::Impl& e, uint32_t idx, uint8_t levels, PixelSnapshot* frame) {
  std::atomic<uint8_t>& slot = e.levels[idx];
  // Unchanged levels (the usual case for a still view) leave the shared cache line clean.
  if (slot.load(std::memory_order_relaxed) != levels) slot.store(levels, std::memory_order_relaxed);
  if (frame) frame->levels = levels;
}

}  // namespace frameless
