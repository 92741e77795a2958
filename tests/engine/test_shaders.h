// Cheap synthetic "shaders" for engine and display tests (pure, thread-safe); any thread.
#pragma once
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/base/rng.h"
#include "core/scene/scene.h"
#include "frameless/engine_config.h"

namespace frameless::testing {

// Colour = the camera's eye.x in every channel: a torn read would mix epochs or channels.
inline SampleResult eye_shader(const void*, const CameraBasis& b, float, float, uint64_t) {
  SampleResult r;
  r.color = Vec3(b.eye.x);
  return r;
}

// A smooth image of the continuous position plus seeded noise (so jitter and seeds matter).
inline SampleResult noisy_shader(const void*, const CameraBasis& b, float px, float py, uint64_t seed) {
  Rng rng(seed);
  SampleResult r;
  r.color = Vec3(px / float(b.width), py / float(b.height), 0.5f + 0.1f * b.eye.x) +
            Vec3(0.1f * rng.next_float());
  return r;
}

// Like noisy_shader, but NaN or Inf in columns divisible by 7, and invalid in row 3.
inline SampleResult nan_shader(const void* c, const CameraBasis& b, float px, float py, uint64_t seed) {
  SampleResult r = noisy_shader(c, b, px, py, seed);
  const int x = int(px), y = int(py);
  if (x % 7 == 0) r.color.y = (seed & 1) ? std::numeric_limits<float>::quiet_NaN() : kInfinity;
  if (y == 3) r.valid = false;
  return r;
}

// Throws at pixel (5, 5): a failing render thread.
inline SampleResult throwing_shader(const void* c, const CameraBasis& b, float px, float py,
                                    uint64_t seed) {
  if (int(px) == 5 && int(py) == 5) throw std::runtime_error("shader exploded at (5, 5)");
  return noisy_shader(c, b, px, py, seed);
}

// An empty scene that outlives every engine in a test (engines keep a reference to their scene).
inline const Scene kEmptyScene{};

inline Camera camera_at(float x) {
  Camera c;
  c.eye = Vec3(x, 0.0f, 5.0f);
  c.look = Vec3(x, 0.0f, 0.0f);
  return c;
}

inline EngineConfig test_config(int w, int h, int threads, SampleResult (*fn)(const void*, const CameraBasis&, float, float, uint64_t)) {
  EngineConfig c;
  c.width = w;
  c.height = h;
  c.threads = threads;
  c.chunk_size = 16;
  c.shader.fn = fn;
  return c;
}

}  // namespace frameless::testing
