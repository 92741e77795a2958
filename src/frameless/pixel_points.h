// What reprojection needs of each pixel's newest update (the render cache): its primary hit in
// world space and what it hit, kept beside the states by pixel index like the levels. Written by
// the render thread that owns the pixel inside its publish, read by the display thread with
// relaxed atomics under the point's own sequence lock (race-free under ThreadSanitizer, and never
// a mix of two updates). 32 bytes per pixel.
#pragma once
#include <algorithm>
#include <atomic>
#include <cmath>
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
  // The denoiser's guides (display/denoise.h): shading normal, octahedral 16:16; albedo, RGB8.
  std::atomic<uint32_t> normal{0};
  std::atomic<uint32_t> albedo{0};
  uint32_t unused = 0;
};
static_assert(sizeof(PixelPoint) == 32, "two pixels' points per cache line");

// igi's discontinuity buffer: the running mean of each pixel's indirect light
// (SampleResult::indirect), kept by the pixel's owner with the same restarts and weights as its
// colour mean, by pixel like the points. The display reads it with relaxed atomics: a channel may
// be one update newer than another, which a filter's input tolerates (nothing else reads it).
struct alignas(16) PixelIndirect {
  std::atomic<float> mean[3] = {0.0f, 0.0f, 0.0f};
  uint32_t unused = 0;
};

// A plain copy of one pixel's point.
struct ScenePoint {
  Vec3 p{0.0f};
  uint32_t object = kPointNone;
};
static_assert(sizeof(ScenePoint) == 16);

// A unit normal in 32 bits (octahedral map, 16 bits per coordinate) and back.
inline uint32_t pack_normal(const Vec3& n) {
  const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  if (!(l1 > 0.0f)) return 0;
  float u = n.x / l1, v = n.y / l1;
  if (n.z < 0.0f) {
    const float pu = (1.0f - std::abs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
    v = (1.0f - std::abs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
    u = pu;
  }
  const auto q = [](float x) { return uint32_t(std::lround((std::clamp(x, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f)); };
  return q(u) | q(v) << 16;
}
inline Vec3 unpack_normal(uint32_t b) {
  if (b == 0) return Vec3(0.0f);
  float u = float(b & 0xffffu) / 65535.0f * 2.0f - 1.0f, v = float(b >> 16) / 65535.0f * 2.0f - 1.0f;
  const float z = 1.0f - std::abs(u) - std::abs(v);
  if (z < 0.0f) {
    const float pu = (1.0f - std::abs(v)) * (u >= 0.0f ? 1.0f : -1.0f);
    v = (1.0f - std::abs(u)) * (v >= 0.0f ? 1.0f : -1.0f);
    u = pu;
  }
  return glm::normalize(Vec3(u, v, z));
}
inline uint32_t pack_albedo(const Vec3& a) {
  const auto q = [](float x) { return uint32_t(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); };
  return q(a.x) | q(a.y) << 8 | q(a.z) << 16;
}
inline Vec3 unpack_albedo(uint32_t b) {
  return Vec3(float(b & 255u), float((b >> 8) & 255u), float((b >> 16) & 255u)) * (1.0f / 255.0f);
}

// Render thread, inside the publish (before the closing sequence store), under the point's own
// sequence lock too.
inline void store_point(PixelPoint& slot, const SampleResult& r) {
  write_locked(slot.seq, [&] {
    for (int c = 0; c < 3; ++c) slot.p[c].store(r.position[c], std::memory_order_relaxed);
    slot.object.store(r.object, std::memory_order_relaxed);
    slot.normal.store(pack_normal(r.normal), std::memory_order_relaxed);
    slot.albedo.store(pack_albedo(r.albedo), std::memory_order_relaxed);
  });
}

// What the denoiser reads of a pixel's newest update.
struct PointGuide {
  Vec3 p{0.0f};
  uint32_t object = kPointNone;
  uint32_t normal = 0;  // pack_normal
  uint32_t albedo = 0;  // pack_albedo
};

// Pixels the guided filters work on: surfaces with a normal and an albedo (not the sky, not emitters).
inline bool guided_surface(const PointGuide& g) {
  return g.object >= kPointStatic && g.normal != 0 && g.albedo != 0;
}

// Display thread: the pixel's newest guides, whole, under the point's sequence lock.
inline bool read_guide(const PixelPoint& slot, PointGuide& out, int max_tries = 16) {
  return read_locked(slot.seq, [&] {
    for (int c = 0; c < 3; ++c) out.p[c] = slot.p[c].load(std::memory_order_relaxed);
    out.object = slot.object.load(std::memory_order_relaxed);
    out.normal = slot.normal.load(std::memory_order_relaxed);
    out.albedo = slot.albedo.load(std::memory_order_relaxed);
  }, nullptr, max_tries);
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
