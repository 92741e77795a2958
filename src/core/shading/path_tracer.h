// Unbiased progressive path tracing (issue 26; docs/global-illumination.md): one path per call,
// next-event estimation with multiple importance sampling (power heuristic) for every light
// kind, Russian roulette after three bounces. Pure, any thread.
#pragma once
#include "core/geometry/surface.h"
#include "core/scene/dynamic.h"
#include "core/scene/scene.h"
#include "core/shading/direct_light.h"

namespace frameless {

struct PathOptions {
  LightStrategy strategy = LightStrategy::kMis;
  int max_bounces = -1;  // scattering events; -1: settings.max_depth. 1 gives direct light only
};

// Radiance along `ray` (unit direction) by one path with random numbers from `seed`. frame:
// what moves at the sample's instant (null: the scene as loaded). known_hit (optional): the
// static scene's closest hit of `ray`. first_hit/first_point (optional) receive the primary
// hit; bounces (optional) the number of scattering events the path took; first_albedo
// (optional) the primary hit's guide_albedo (the display's denoiser reads it).
Vec3 trace_path(const Scene& scene, const Ray& ray, uint64_t seed, const DynamicFrame* frame = nullptr,
                const Hit* known_hit = nullptr, Hit* first_hit = nullptr,
                SurfacePoint* first_point = nullptr, int* bounces = nullptr,
                const PathOptions& options = {}, Vec3* first_albedo = nullptr);

}  // namespace frameless
