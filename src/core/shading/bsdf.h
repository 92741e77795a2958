// Scattering functions for light that bounces (issue 26's path tracer): the physically based
// readings of Parker's classes, each with its value, its sampling and its density. Pure
// functions on a local shading frame (normal = +z, directions unit and pointing away from the
// surface); any thread.
#pragma once
#include "core/base/types.h"
#include "core/geometry/shading_frame.h"  // the local frame

namespace frameless {

// One sampled direction: wi, the estimator weight f cos(theta_i) / pdf (0 when the sample falls
// below the surface), and its density per solid angle.
struct BsdfSample {
  Vec3 wi{0.0f, 0.0f, 1.0f};
  Vec3 weight{0.0f};
  float pdf = 0.0f;
};

// Cosine-weighted hemisphere direction from (u1, u2) in [0, 1)^2 (Malley's method).
Vec3 sample_cosine_hemisphere(float u1, float u2);
// Uniform direction on the unit sphere from (u1, u2) in [0, 1)^2 (density 1 / (4 pi)).
Vec3 sample_uniform_sphere(float u1, float u2);

// Diffuse: Lambertian, f = albedo / pi.
Vec3 lambert_eval(const Vec3& albedo, const Vec3& wo, const Vec3& wi);
float lambert_pdf(const Vec3& wo, const Vec3& wi);
BsdfSample lambert_sample(const Vec3& albedo, const Vec3& wo, float u1, float u2);

// Metal's and the highlights' lobe: the normalized Phong lobe of Lafortune and Willems 1994,
// f = ks (N + 2) / (2 pi) cos^N(alpha), alpha the angle between wi and wo's mirror direction.
// Its directional albedo is ks at normal incidence and less elsewhere (the lobe's part below
// the surface is lost), so it never creates energy.
Vec3 phong_eval(const Vec3& ks, float exponent, const Vec3& wo, const Vec3& wi);
float phong_pdf(float exponent, const Vec3& wo, const Vec3& wi);
BsdfSample phong_sample(const Vec3& ks, float exponent, const Vec3& wo, float u1, float u2);

// Polished's diffuse base: the coupled model of Shirley, Hu, Smits and Lafortune 1997, whose
// clamped-RGB form is Parker et al.'s equation 2:
//   f = 21 / (20 pi) (1 - r0) kd (1 - (1 - cos theta_i)^5) (1 - (1 - cos theta_o)^5).
// 21 / (20 pi) normalises it: its directional albedo at normal incidence is (1 - r0) kd, what
// the Schlick coat of reflectance r0 leaves to the base (the hemisphere integral of
// (1 - (1 - c)^5) c is 20 pi / 21). It is sampled like a Lambertian surface.
// r0 per channel: the coat of a coloured r0 leaves each channel its own 1 - r0.
Vec3 coupled_diffuse_eval(const Vec3& kd, const Vec3& r0, const Vec3& wo, const Vec3& wi);

// Microfacet reflection for glTF's metallic-roughness materials: GGX distribution (Walter et al.
// 2007) with its separable Smith masking and Schlick's Fresnel of reflectance f0 at normal
// incidence; alpha = roughness^2 (clamped to [1e-3, 1]). Half vectors are sampled from D(h) cos.
Vec3 ggx_eval(const Vec3& f0, float alpha, const Vec3& wo, const Vec3& wi);
float ggx_pdf(float alpha, const Vec3& wo, const Vec3& wi);
BsdfSample ggx_sample(const Vec3& f0, float alpha, const Vec3& wo, float u1, float u2);

// glTF's non-metals (a dielectric base): the GGX coat of reflectance f0 (glTF's 0.04) and
// roughness over the coupled diffuse base of kd, which keeps what a coat of f0 leaves. Sampled by
// picking the coat with probability ggx_coat_pick(f0, wo) (its mean Schlick reflectance at wo,
// kept in [0.1, 0.9]) and the base otherwise; the density is that mixture.
float ggx_coat_pick(const Vec3& f0, const Vec3& wo);
Vec3 ggx_coated_eval(const Vec3& kd, const Vec3& f0, float alpha, const Vec3& wo, const Vec3& wi);
float ggx_coated_pdf(const Vec3& f0, float alpha, const Vec3& wo, const Vec3& wi);
BsdfSample ggx_coated_sample(const Vec3& kd, const Vec3& f0, float alpha, const Vec3& wo, float u0,
                             float u1, float u2);

}  // namespace frameless
