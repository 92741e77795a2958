// Where the path tracer's next-event estimation aims (docs/global-illumination.md): Parker's
// point, spherical and directional lights, the emissive triangles (EmitterTable, by power) and
// the constant environment; with the densities a BSDF-sampled ray needs for multiple importance
// sampling. Pure, any thread.
//
// Parker's lights keep the seed's convention that a light of colour l_e lights a Lambertian
// surface of albedo k_d as k_d l_e (n.l) whatever its distance: it delivers irradiance
// pi l_e (n.l), so the Whitted diffuse term is exactly what one bounce of path tracing gives. A
// light with an extent spreads that over the cone it subtends at the receiver, with radiance
// l_e / sin^2(theta) inside it (a cone's projected solid angle is pi sin^2(theta) cos(beta)).
// They are seen only by next-event estimation and by BSDF-sampled rays of smooth surfaces, never
// by camera rays or mirrors (as in Whitted, where highlights stand in for their images).
#pragma once
#include "core/scene/dynamic.h"
#include "core/scene/light.h"
#include "core/scene/scene.h"

namespace frameless {

struct LightSample {
  Vec3 wi{0.0f};          // unit, toward the light
  float tmax = kInfinity; // shadow ray length (just short of the light)
  Vec3 radiance{0.0f};    // arriving radiance; for a delta light pi l_e (irradiance at n.l = 1)
  float pdf = 0.0f;       // density per solid angle; 0 for a delta light (a point, a hard sun)
};

// One direction toward Parker light `light` from p, from two uniform numbers; false when p gets
// no light from it (inside a spherical light).
bool sample_parker_light(const Light& light, const Vec3& p, float u1, float u2, LightSample& out);

// A BSDF-sampled ray from p along unit d whose nearest surface lies at t_hit (infinity: it
// escapes): whether it reaches Parker light `light` (one with an extent) first, and if so the
// radiance it brings and the density sample_parker_light has for d.
bool parker_light_hit(const Light& light, const Vec3& p, const Vec3& d, float t_hit,
                      Vec3& radiance, float& pdf);

// One point on an emissive triangle of the table, chosen by power, seen from p.
bool sample_emitter(const Scene& scene, const DynamicFrame* frame, const Vec3& p, float u0,
                    float u1, float u2, LightSample& out);

// Density per solid angle with which sample_emitter picks the point at distance t along the
// unit direction d on table entry `index` (a triangle with geometric unit normal n).
float emitter_pdf(const Scene& scene, uint32_t index, const Vec3& d, const Vec3& n, float t);

// The environment: an image map by its importance (luminance x sin(theta)), or the constant
// settings.background uniformly over the sphere. false when it gives nothing.
bool sample_environment(const Scene& scene, float u1, float u2, LightSample& out);
// The density sample_environment has at unit direction d.
float environment_pdf(const Scene& scene, const Vec3& d);
// Whether the environment emits at all (skip its sampling otherwise).
bool environment_emits(const Scene& scene);

}  // namespace frameless
