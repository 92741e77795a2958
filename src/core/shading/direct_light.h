// Next-event estimation at one vertex (Parker's lights, emissive triangles, the environment) and
// the pieces the path tracer and instant global illumination share: MIS weights, Beer's law,
// the textured material at a hit. Pure, any thread.
#pragma once
#include <cmath>

#include "core/base/rng.h"
#include "core/scene/dynamic.h"
#include "core/scene/scene.h"
#include "core/shading/path_material.h"

namespace frameless {

// How light sources are found: both strategies weighted by MIS (the renderer), or one alone
// (the tests check that all three have the same mean).
enum class LightStrategy : uint8_t { kMis, kLightOnly, kBsdfOnly };

// Power heuristic (Veach 1997, beta = 2): the weight of the strategy with density a.
inline float power_weight(float a, float b) {
  if (!(a > 0.0f)) return 0.0f;
  const float r = b / a;  // a ratio: squares of large densities would overflow
  return std::isfinite(r) ? 1.0f / (1.0f + r * r) : 0.0f;
}

// Weight of a light-sampled estimate (density pl) against BSDF sampling (density pb).
inline float light_weight(LightStrategy s, float pl, float pb) {
  return s == LightStrategy::kMis ? power_weight(pl, pb) : s == LightStrategy::kLightOnly ? 1.0f : 0.0f;
}
// Weight of a BSDF-sampled hit of a light that light sampling also finds.
inline float bsdf_weight(LightStrategy s, float pb, float pl) {
  return s == LightStrategy::kMis ? power_weight(pb, pl) : s == LightStrategy::kBsdfOnly ? 1.0f : 0.0f;
}

// Beer's law over distance t (infinite: what an absorbing channel never gets back).
inline Vec3 beer(const Vec3& extinction, float t) {
  Vec3 out;
  for (int k = 0; k < 3; ++k)
    out[k] = extinction[k] > 0.0f ? (t < kInfinity ? std::exp(-extinction[k] * t) : 0.0f) : 1.0f;
  return out;
}

// The material at a hit, textured (instances in object space; moving objects carry none).
MaterialParams material_at(const Scene& scene, const DynamicFrame* frame, const Ray& ray,
                           const Hit& hit, SurfacePoint& sp);

// One path's view of the lights: the scene, what moves, the strategy and the path's numbers.
struct DirectLight {
  const Scene& scene;
  const DynamicFrame* frame;
  LightStrategy strategy;
  Rng rng;
  bool environment;      // the environment emits: sample it
  bool extended_lights;  // some Parker light has an extent (BSDF rays may reach it)
  // The environment is black and sampled only to measure that skipping it pays (SkipConfig::
  // emitters off): its numbers come from a copy of the stream, so the image stays bit-identical.
  bool black_environment = false;
};

// Direct light leaving surface s towards its viewer: Parker's lights (through the smooth part,
// MIS-weighted where they have an extent, and through the highlight lobes), one emissive
// triangle and one environment direction (through the smooth part). origin: the offset point
// shadow rays start from; extinction: of the dielectric the vertex is inside.
Vec3 direct_light(DirectLight& st, const PathSurface& s, const Vec3& origin, const Vec3& extinction);

}  // namespace frameless
