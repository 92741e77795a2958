// One-shot parallel render of a whole image (the `render` command and references); the caller's
// thread waits while worker threads take 16x16 tiles from an atomic counter.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace frameless {

struct TileRenderOptions {
  int spp = 16;
  int threads = 1;
  bool jitter = true;
  uint32_t first_sample = 0;  // sample indices [first_sample, first_sample + spp) per pixel
  double time = 0.0;          // seconds: where moving objects are (core/scene/dynamic.h)
  // Called from the caller's thread about ten times a second with the fraction done.
  std::function<void(double)> progress;
};

// Planes of a finished render; row 0 is the top row.
struct RenderedImage {
  int width = 0, height = 0;
  std::vector<float> rgb;      // 3 floats per pixel: mean radiance of the valid samples
  std::vector<float> depth;    // distance from the eye along the first sample's primary ray
  std::vector<float> normal;   // 3 floats per pixel: first sample's shading normal
  std::vector<float> samples;  // valid samples averaged per pixel
  std::vector<uint8_t> levels; // deepest reflection/refraction level over the valid samples
  uint64_t dropped = 0;        // samples dropped for NaN/Inf
  double seconds = 0.0;        // wall time of the render
};

RenderedImage render_tiles(const Scene& scene, const CameraBasis& camera,
                           const TileRenderOptions& options);

// Flush denormals to zero on the calling thread (render threads call this first).
void enable_flush_to_zero();

}  // namespace frameless
