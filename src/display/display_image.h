// The displayed image and its per-pixel layers, as produced by the display thread at one tick;
// consumers (viewer, capture, stats) get read-only copies.
#pragma once
#include <cstdint>
#include <vector>

#include "frameless/engine_config.h"

namespace frameless {

// What one display tick did.
struct FrameInfo {
  uint64_t index = 0;             // display tick number, 0-based
  double wall_time = 0;           // seconds since the display started (steady clock)
  double virtual_time = 0;        // engine seconds (virtual clock in deterministic mode)
  double interval = 0;            // measured seconds since the previous tick (wall; virtual in deterministic mode)
  uint64_t samples = 0;           // samples rendered since the previous tick
  uint64_t pixels_updated = 0;    // pixels blended at this tick
  double coverage = 0;            // fraction of pixels whose newest sample used the newest camera
  uint32_t newest_epoch = 0;      // newest published camera epoch at this tick
  RenderMode mode = RenderMode::frameless;  // engine mode the pixels came from
  uint64_t dropped_samples = 0;   // NaN/Inf samples dropped by the engine since its start
  uint64_t rejected = 0;          // non-finite values stopped at the display since its start
};

// Linear float RGB plus layers; row 0 is the top row; pixel i = y * width + x. With reprojection
// on, rgb and epoch belong to the content shown (they move with it when the camera moves); the
// other layers describe the newest update blended at the pixel itself, as the engine's pixel does.
struct DisplayImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;             // 3 floats per pixel, always finite
  std::vector<float> last_update;     // engine seconds of the pixel's newest sample; -1: never
  std::vector<uint32_t> sample_count; // samples since the pixel's camera epoch began
  std::vector<float> variance;        // luminance variance since the epoch began (0 if untracked)
  std::vector<uint32_t> epoch;        // camera epoch of the pixel's newest sample (0: never)
  std::vector<uint8_t> levels;        // deepest reflection/refraction level of its newest update
  FrameInfo info;                     // the tick that produced this image

  size_t pixels() const { return size_t(width) * size_t(height); }
  // Time since pixel i's last update, in seconds (infinite if never updated).
  float age(size_t i) const;
  // Sets size and clears every layer (black, never updated).
  void reset(int w, int h);
};

}  // namespace frameless
