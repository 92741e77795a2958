// Next-event estimation's targets: Parker's lights by the cone they subtend, emissive triangles
// by power and area, the constant environment over the sphere.
#include "core/shading/light_sampling.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/shading_frame.h"
#include "core/shading/bsdf.h"
#include "core/scene/texturing.h"

namespace frameless {
namespace {

// Shadow rays stop this fraction short of the light, so its own surface never occludes it.
constexpr float kShortOfLight = 1.0f - 0x1.0p-12f;

// The cone a light subtends: 1 - cos(theta) from sin^2(theta) (stable for small cones).
inline float one_minus_cos(float sin2) { return sin2 / (1.0f + std::sqrt(std::max(0.0f, 1.0f - sin2))); }

// Uniform direction in the cone of half-angle theta around unit axis.
Vec3 sample_cone(const Vec3& axis, float omc, float u1, float u2) {
  const float cos_a = 1.0f - u1 * omc;
  const float sin_a = std::sqrt(std::max(0.0f, (1.0f - cos_a) * (1.0f + cos_a)));
  const float phi = 2.0f * kPi * u2;
  return glm::normalize(make_shading_frame(axis).to_world(
      Vec3(sin_a * std::cos(phi), sin_a * std::sin(phi), cos_a)));
}

// sin^2 of the cone a Parker light subtends from p (0 for a point or a hard sun; -1 when p is
// inside a spherical light).
float cone_sin2(const Light& light, const Vec3& p) {
  if (light.kind == LightKind::kDirectional) {
    const float s = std::sin(light.angular_radius);
    return light.angular_radius > 0.0f ? s * s : 0.0f;
  }
  if (!(light.radius > 0.0f)) return 0.0f;
  const Vec3 to = light.position - p;
  const float d2 = glm::dot(to, to);
  const float r2 = light.radius * light.radius;
  return d2 > r2 ? r2 / d2 : -1.0f;
}

}  // namespace

bool sample_parker_light(const Light& light, const Vec3& p, float u1, float u2, LightSample& out) {
  const float sin2 = cone_sin2(light, p);
  if (sin2 < 0.0f) return false;
  const bool sun = light.kind == LightKind::kDirectional;
  const Vec3 axis = sun ? -light.direction : glm::normalize(light.position - p);
  if (sin2 == 0.0f) {  // a delta light
    out.wi = axis;
    out.tmax = sun ? kInfinity : glm::length(light.position - p) * kShortOfLight;
    out.radiance = kPi * light.color;
    out.pdf = 0.0f;
    return out.tmax > 0.0f;
  }
  const float omc = one_minus_cos(sin2);
  out.wi = sample_cone(axis, omc, u1, u2);
  out.radiance = light.color / sin2;
  out.pdf = 1.0f / (2.0f * kPi * omc);
  out.tmax = kInfinity;
  if (!sun) {  // to the near side of the sphere along wi
    const Vec3 to = light.position - p;
    const float b = glm::dot(out.wi, to);
    const float disc = std::max(0.0f, light.radius * light.radius - (glm::dot(to, to) - b * b));
    out.tmax = (b - std::sqrt(disc)) * kShortOfLight;
  }
  return out.tmax > 0.0f && std::isfinite(out.pdf);
}

bool parker_light_hit(const Light& light, const Vec3& p, const Vec3& d, float t_hit,
                      Vec3& radiance, float& pdf) {
  const float sin2 = cone_sin2(light, p);
  if (!(sin2 > 0.0f)) return false;
  const float omc = one_minus_cos(sin2);
  if (light.kind == LightKind::kDirectional) {
    if (t_hit < kInfinity) return false;  // the sun is behind everything
    if (glm::dot(d, -light.direction) < 1.0f - omc) return false;
  } else {
    const Vec3 to = light.position - p;
    const float b = glm::dot(d, to);
    const float disc = light.radius * light.radius - (glm::dot(to, to) - b * b);
    if (b <= 0.0f || disc < 0.0f) return false;
    if (b - std::sqrt(disc) >= t_hit) return false;  // a surface is in front of it
  }
  radiance = light.color / sin2;
  pdf = 1.0f / (2.0f * kPi * omc);
  return std::isfinite(pdf);
}

bool sample_emitter(const Scene& scene, const DynamicFrame* frame, const Vec3& p, float u0,
                    float u1, float u2, LightSample& out) {
  const EmitterTable& table = scene.emitters;
  const uint32_t index = table.pick(u0);
  const uint32_t prim = table.prims[index];
  const Geometry& g = scene.geometry;
  const TrianglePoint tp = triangle_point(scene, prim, u1, u2);
  const Vec3 q = tp.p;
  const float bu = tp.u, bv = tp.v;
  const Vec3 to = q - p;
  const float dist2 = glm::dot(to, to);
  if (!(dist2 > 0.0f)) return false;
  const float dist = std::sqrt(dist2);
  out.wi = to / dist;
  Vec3 n = tp.n;
  out.pdf = emitter_pdf(scene, index, out.wi, n, dist);
  if (!(out.pdf > 0.0f) || !std::isfinite(out.pdf)) return false;
  // End the shadow ray at q moved off the emitter towards p by the triangle's rounding scale,
  // so neither the emitter itself nor a blocker next to it is misjudged at any scene scale.
  if (glm::dot(n, out.wi) > 0.0f) n = -n;
  out.tmax = glm::dot(offset_ray_origin(q, n, tp.scale) - p, out.wi);
  if (!(out.tmax > 0.0f)) return false;
  const uint16_t id = prim < g.triangle_material.size() ? g.triangle_material[prim] : 0;
  MaterialParams m = frame_material(scene, frame, id);
  if (m.emission_tex != kNoTexture || m.cutout()) {  // the texture at the sampled point
    Ray ray;
    ray.org = p;
    ray.dir = out.wi;
    Hit hit;
    hit.t = dist;
    hit.prim = prim;
    hit.u = bu;
    hit.v = bv;
    // A hole of a cut-out emits nothing (BSDF rays pass through it too).
    if (m.cutout() && !cutout_opaque(scene, prim, ray, dist, bu, bv)) return false;
    SurfacePoint sp = surface_point(g, ray, hit);
    apply_textures(scene, ray, hit, m, sp);
  }
  out.radiance = m.emission;
  return max_component(out.radiance) > 0.0f;
}

float emitter_pdf(const Scene& scene, uint32_t index, const Vec3& d, const Vec3& n, float t) {
  const EmitterTable& table = scene.emitters;
  const float cos_l = std::abs(glm::dot(n, d));
  if (!(cos_l > 0.0f)) return 0.0f;
  return table.pmf(index) / table.area[index] * (t * t) / cos_l;
}

constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPi);

bool sample_environment(const Scene& scene, float u1, float u2, LightSample& out) {
  out.tmax = kInfinity;
  if (const EnvironmentMap* env = scene.environment.get()) {
    if (!env->sample(u1, u2, out.wi, out.pdf)) return false;
    out.radiance = env->radiance(out.wi);
    return true;
  }
  out.wi = sample_uniform_sphere(u1, u2);
  out.radiance = scene.settings.background;
  out.pdf = kUniformSpherePdf;
  return true;
}

float environment_pdf(const Scene& scene, const Vec3& d) {
  return scene.environment ? scene.environment->pdf(d) : kUniformSpherePdf;
}

bool environment_emits(const Scene& scene) {
  return scene.environment ? !scene.environment->black() : max_component(scene.settings.background) > 0.0f;
}

}  // namespace frameless
