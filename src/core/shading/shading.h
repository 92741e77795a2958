// Parker et al. 1999 shading (section 3.1): material classes, Schlick, ambient, point/spherical
// lights and Whitted recursion; pure functions called on render threads (any thread).
#pragma once
#include "core/geometry/surface.h"
#include "core/scene/dynamic.h"
#include "core/scene/scene.h"
#include "core/shading/optics.h"

namespace frameless {

// Hemisphere ambient of section 3.1.1 (Nusselt's analog): A at theta = 0, (A + B)/2 at pi/2,
// B at pi, theta the angle between the shading normal n (unit) and the ambient axis.
Vec3 hemisphere_ambient(const Vec3& a, const Vec3& b, const Vec3& axis, const Vec3& n);

// l_a at point p for shading normal n under any ambient kind (none, constant, hemisphere,
// irradiance volume: E(p, n) / pi, so k_d l_a is what a Lambertian surface reflects of it).
Vec3 ambient_light(const Ambient& ambient, const Vec3& p, const Vec3& n);

// Radiance along `ray` (unit direction) in the medium `medium` (nullptr: outside every
// dielectric). depth counts bounces already taken, weight is the ray's accumulated ray-tree weight
// (for pruning). Returns the radiance; `first_hit` (optional) receives the closest hit.
Vec3 trace_radiance(const Scene& scene, const Ray& ray, int depth, const Vec3& weight,
                    const MaterialParams* medium, Hit* first_hit = nullptr,
                    SurfacePoint* first_point = nullptr);

// trace_radiance on a given shading path (ShadeBits, core/scene/scene_analysis.h): trace_sample picks
// the path once per sample. A path must keep every bit the scene needs (shade_path does).
// rng_seed drives the stochastic choices of the sample (area-sampled shadows); frame (optional)
// holds what moves at the sample's instant (core/scene/dynamic.h). known_hit (optional): the static
// scene's closest hit of `ray`, already found (a ray packet); moving objects are still tested.
// levels (optional) receives the deepest reflection/refraction level traced (0: the ray alone).
Vec3 trace_radiance_path(const Scene& scene, uint32_t path, const Ray& ray, int depth,
                         const Vec3& weight, const MaterialParams* medium, Hit* first_hit = nullptr,
                         SurfacePoint* first_point = nullptr, uint64_t rng_seed = 0,
                         const DynamicFrame* frame = nullptr, const Hit* known_hit = nullptr,
                         int* levels = nullptr);

}  // namespace frameless
