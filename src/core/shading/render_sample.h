// The pure per-sample entry point of the core: one camera ray, shaded with Parker's model.
// Deterministic in its inputs; safe to call from any number of threads on a finalized Scene.
#pragma once
#include "core/scene/camera.h"
#include "core/scene/dynamic.h"
#include "core/scene/scene.h"

namespace frameless {

struct SampleResult {
  Vec3 color{0.0f};   // radiance; finite whenever valid
  float depth = kInfinity;  // distance along the primary ray from the eye; +inf on a miss
  Vec3 normal{0.0f};  // shading normal at the primary hit (zero on a miss)
  bool valid = true;  // false: a NaN/Inf arose and the sample must be dropped (and counted)
  uint8_t levels = 0; // deepest reflection/refraction level traced (seed figure 1d), saturating
  // What reprojection needs (the render cache): the primary hit in world space, moved onto the
  // pixel centre's ray at the same view depth (the centre ray's direction, not normalized, on a
  // miss), and what
  // was hit (kPoint* below).
  Vec3 position{0.0f};
  uint32_t object = 0;
  // The primary hit's albedo for the display's denoiser (path and igi only; 0 otherwise): the
  // diffuse colour, a metal's k_s, 1 for glass.
  Vec3 albedo{0.0f};
  // igi only: the virtual point lights' share of `color` at the primary hit (the display's
  // discontinuity buffer filters it over neighbours on the same surface); 0 otherwise.
  Vec3 indirect{0.0f};
};

// SampleResult::object: nothing yet, the sky (position is a direction), the static scene, a
// dynamic object (kPointDynamic + its index) or an instance (kPointInstance + its index): the
// last two may move, so their reprojected pixels are stale.
inline constexpr uint32_t kPointNone = 0;
inline constexpr uint32_t kPointSky = 1;
inline constexpr uint32_t kPointStatic = 2;
inline constexpr uint32_t kPointDynamic = 0x10000000u;
inline constexpr uint32_t kPointInstance = 0x20000000u;
inline bool point_may_move(uint32_t object) { return object >= kPointDynamic; }

// Traces the primary ray through continuous image position (px, py); rng_seed drives any
// stochastic choice inside shading. frame: the moving objects, lights and materials at the
// sample's instant (core/scene/dynamic.h); null renders the scene as loaded, without dynamic objects.
// known_hit (optional): the static scene's closest hit of this camera ray, from primary_hits.
// sample_index: the sample's index among its pixel's samples (igi picks the VPL set by it).
SampleResult trace_sample(const Scene& scene, const CameraBasis& camera, float px, float py,
                          uint64_t rng_seed, const DynamicFrame* frame = nullptr,
                          const Hit* known_hit = nullptr, uint32_t sample_index = 0);

// The static scene's closest hits of n camera rays through (px[i], py[i]), traced as coherent
// packets (Accel::intersect_packet): exactly the hits single rays find, so trace_sample with
// them returns the same samples bit for bit. Any n; consecutive rays should be neighbours.
// frame: its moved instances are the ones hit (null: the scene as built).
void primary_hits(const Scene& scene, const CameraBasis& camera, int n, const float* px,
                  const float* py, Hit* hits, const DynamicFrame* frame = nullptr);

// Sample `sample_index` of pixel (x, y): jitter offset and rng seed derived from
// (x, y, sample_index, scene.settings.seed). jitter=false samples the pixel centre.
SampleResult render_sample(const Scene& scene, const CameraBasis& camera, int x, int y,
                           uint32_t sample_index, bool jitter = true,
                           const DynamicFrame* frame = nullptr);

}  // namespace frameless
