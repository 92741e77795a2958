// Scattering functions of the path tracer: values, importance sampling and densities on the
// local shading frame (normal = +z). Directions below the surface scatter nothing.
#include "core/shading/bsdf.h"

#include <algorithm>
#include <cmath>

#include "core/shading/optics.h"

namespace frameless {
namespace {

constexpr float kInvPi = 1.0f / kPi;

inline bool above(const Vec3& w) { return w.z > 0.0f; }

inline Vec3 mirror(const Vec3& wo) { return Vec3(-wo.x, -wo.y, wo.z); }

// Directions around `axis` at angle acos(cos_t) and azimuth phi.
Vec3 around(const Vec3& axis, float cos_t, float phi) {
  const ShadingFrame f = make_shading_frame(axis);
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
  return f.to_world(Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t));
}

inline BsdfSample finish(const Vec3& wi, const Vec3& f, float pdf) {
  BsdfSample s;
  s.wi = wi;
  s.pdf = pdf;
  if (above(wi) && pdf > 0.0f && std::isfinite(pdf)) s.weight = f * (wi.z / pdf);
  return s;
}

// GGX normal distribution and the Smith masking of one direction.
float ggx_d(float alpha, float cos_h) {
  const float a2 = alpha * alpha;
  const float t = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * t * t);
}

float ggx_g1(float alpha, float cos_v) {
  const float a2 = alpha * alpha;
  return 2.0f * cos_v / (cos_v + std::sqrt(a2 + (1.0f - a2) * cos_v * cos_v));
}

inline float clamp_alpha(float alpha) { return std::clamp(alpha, 1e-3f, 1.0f); }

}  // namespace

Vec3 sample_cosine_hemisphere(float u1, float u2) {
  const float r = std::sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1)));
}

Vec3 sample_uniform_sphere(float u1, float u2) {
  const float z = 1.0f - 2.0f * u1, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

Vec3 lambert_eval(const Vec3& albedo, const Vec3& wo, const Vec3& wi) {
  return above(wo) && above(wi) ? albedo * kInvPi : Vec3(0.0f);
}

float lambert_pdf(const Vec3& wo, const Vec3& wi) {
  return above(wo) && above(wi) ? wi.z * kInvPi : 0.0f;
}

BsdfSample lambert_sample(const Vec3& albedo, const Vec3& wo, float u1, float u2) {
  const Vec3 wi = sample_cosine_hemisphere(u1, u2);
  return finish(wi, lambert_eval(albedo, wo, wi), lambert_pdf(wo, wi));
}

Vec3 phong_eval(const Vec3& ks, float exponent, const Vec3& wo, const Vec3& wi) {
  if (!above(wo) || !above(wi)) return Vec3(0.0f);
  const float c = glm::dot(mirror(wo), wi);
  if (c <= 0.0f) return Vec3(0.0f);
  return ks * ((exponent + 2.0f) * 0.5f * kInvPi * std::pow(c, exponent));
}

float phong_pdf(float exponent, const Vec3& wo, const Vec3& wi) {
  if (!above(wo) || !above(wi)) return 0.0f;
  const float c = glm::dot(mirror(wo), wi);
  return c > 0.0f ? (exponent + 1.0f) * 0.5f * kInvPi * std::pow(c, exponent) : 0.0f;
}

BsdfSample phong_sample(const Vec3& ks, float exponent, const Vec3& wo, float u1, float u2) {
  // cos(alpha) = u1^(1 / (N + 1)) draws alpha from the lobe cos^N(alpha) per solid angle.
  const Vec3 wi = around(mirror(wo), std::pow(u1, 1.0f / (exponent + 1.0f)), 2.0f * kPi * u2);
  return finish(wi, phong_eval(ks, exponent, wo, wi), phong_pdf(exponent, wo, wi));
}

Vec3 coupled_diffuse_eval(const Vec3& kd, const Vec3& r0, const Vec3& wo, const Vec3& wi) {
  if (!above(wo) || !above(wi)) return Vec3(0.0f);
  const float k = 21.0f / (20.0f * kPi) * (1.0f - pow5(1.0f - std::min(wi.z, 1.0f))) *
                  (1.0f - pow5(1.0f - std::min(wo.z, 1.0f)));
  return kd * (Vec3(1.0f) - r0) * k;
}

Vec3 ggx_eval(const Vec3& f0, float alpha, const Vec3& wo, const Vec3& wi) {
  if (!above(wo) || !above(wi)) return Vec3(0.0f);
  alpha = clamp_alpha(alpha);
  const Vec3 h = glm::normalize(wo + wi);
  const float d = ggx_d(alpha, h.z);
  const float g = ggx_g1(alpha, wo.z) * ggx_g1(alpha, wi.z);
  return schlick(glm::dot(wo, h), f0) * (d * g / (4.0f * wo.z * wi.z));
}

float ggx_pdf(float alpha, const Vec3& wo, const Vec3& wi) {
  if (!above(wo) || !above(wi)) return 0.0f;
  alpha = clamp_alpha(alpha);
  const Vec3 h = glm::normalize(wo + wi);
  const float oh = glm::dot(wo, h);
  return oh > 0.0f ? ggx_d(alpha, h.z) * h.z / (4.0f * oh) : 0.0f;
}

// wo reflected about a half vector drawn from D(h) cos(theta_h): tan^2(theta_h) = alpha^2 u1 / (1 - u1).
static Vec3 ggx_reflect_sample(float alpha, const Vec3& wo, float u1, float u2) {
  alpha = clamp_alpha(alpha);
  const float cos_h = std::sqrt((1.0f - u1) / (1.0f + (alpha * alpha - 1.0f) * u1));
  const Vec3 h = around(Vec3(0.0f, 0.0f, 1.0f), cos_h, 2.0f * kPi * u2);
  return 2.0f * glm::dot(wo, h) * h - wo;
}

BsdfSample ggx_sample(const Vec3& f0, float alpha, const Vec3& wo, float u1, float u2) {
  const Vec3 wi = ggx_reflect_sample(alpha, wo, u1, u2);
  return finish(wi, ggx_eval(f0, alpha, wo, wi), ggx_pdf(alpha, wo, wi));
}

float ggx_coat_pick(const Vec3& f0, const Vec3& wo) {
  const Vec3 f = schlick(std::clamp(wo.z, 0.0f, 1.0f), f0);
  return std::clamp((f.x + f.y + f.z) * (1.0f / 3.0f), 0.1f, 0.9f);
}

Vec3 ggx_coated_eval(const Vec3& kd, const Vec3& f0, float alpha, const Vec3& wo, const Vec3& wi) {
  return ggx_eval(f0, alpha, wo, wi) + coupled_diffuse_eval(kd, f0, wo, wi);
}

float ggx_coated_pdf(const Vec3& f0, float alpha, const Vec3& wo, const Vec3& wi) {
  const float p = ggx_coat_pick(f0, wo);
  return p * ggx_pdf(alpha, wo, wi) + (1.0f - p) * lambert_pdf(wo, wi);
}

BsdfSample ggx_coated_sample(const Vec3& kd, const Vec3& f0, float alpha, const Vec3& wo, float u0,
                             float u1, float u2) {
  const Vec3 wi = u0 < ggx_coat_pick(f0, wo) ? ggx_reflect_sample(alpha, wo, u1, u2) : sample_cosine_hemisphere(u1, u2);
  return finish(wi, ggx_coated_eval(kd, f0, alpha, wo, wi), ggx_coated_pdf(f0, alpha, wo, wi));
}

}  // namespace frameless
