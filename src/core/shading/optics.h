// Optics at interfaces (Parker et al. 1999, section 3.1): Schlick's approximation, reflectance at
// normal incidence, the dielectric's Fresnel weights. Pure functions, any thread.
#pragma once
#include <cmath>

#include "core/base/types.h"

namespace frameless {

// x^5 in three products (Schlick's factor, Parker's polished view factor).
inline float pow5(float x) {
  const float x2 = x * x;
  return x2 * x2 * x;
}

// Parker's highlight (h . n)^N with h the half vector of unit e and l (0 where h . n <= 0).
inline float phong_lobe(const Vec3& n, const Vec3& e, const Vec3& l, float exponent) {
  const Vec3 h = glm::normalize(e + l);
  const float hn = glm::dot(h, n);
  return hn > 0.0f ? std::pow(hn, exponent) : 0.0f;
}

// Mirror direction of d about the shading normal ns, about the geometric normal ng where the
// shading normal would send it below the surface.
inline Vec3 mirror_direction(const Vec3& d, const Vec3& ns, const Vec3& ng) {
  Vec3 r = d - 2.0f * glm::dot(d, ns) * ns;
  if (glm::dot(r, ng) <= 0.0f) r = d - 2.0f * glm::dot(d, ng) * ng;
  return r;
}

// Schlick's approximation k_s = R0 + (1 - R0)(1 - cos)^5, cos clamped to [0, 1].
float schlick(float cos_theta, float r0);
Vec3 schlick(float cos_theta, const Vec3& r0);

// Normal-incidence reflectance ((n - 1) / (n + 1))^2 of an interface to a medium of index ior.
float r0_from_ior(float ior);

// Reflection and transmission weights at a dielectric interface. cos_i = e . n >= 0 on the
// incident side; eta = n_incident / n_transmitted. Total internal reflection gives ks = 1, kt = 0.
struct FresnelTerms {
  float ks = 1.0f;
  float kt = 0.0f;
  float cos_t = 0.0f;  // cosine of the transmitted direction with -n (0 under TIR)
  bool total_internal_reflection = true;
};
FresnelTerms dielectric_fresnel(float cos_i, float eta, float r0);

}  // namespace frameless
