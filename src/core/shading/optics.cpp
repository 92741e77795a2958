// Optics at interfaces: Schlick's Fresnel approximation (Parker et al. 1999, section 3.1) and
// the dielectric's reflection and transmission weights. Compiled without FMA contraction, like
// shading.cpp, so every caller gets the same rounding (src/core/shading/CMakeLists.txt).
#include "core/shading/optics.h"

#include <algorithm>
#include <cmath>

namespace frameless {

float schlick(float cos_theta, float r0) {
  const float c = std::clamp(cos_theta, 0.0f, 1.0f);
  return r0 + (1.0f - r0) * pow5(1.0f - c);
}

Vec3 schlick(float cos_theta, const Vec3& r0) {
  const float c = std::clamp(cos_theta, 0.0f, 1.0f);
  return r0 + (Vec3(1.0f) - r0) * pow5(1.0f - c);
}

float r0_from_ior(float ior) {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

FresnelTerms dielectric_fresnel(float cos_i, float eta, float r0) {
  FresnelTerms f;
  const float c = std::clamp(cos_i, 0.0f, 1.0f);
  const float sin2_t = eta * eta * (1.0f - c * c);
  if (sin2_t >= 1.0f) return f;  // total internal reflection: everything reflects
  f.cos_t = std::sqrt(1.0f - sin2_t);
  f.total_internal_reflection = false;
  // Schlick with the cosine of the larger angle (the side of the less dense medium), the usual
  // choice that keeps k_s symmetric between entering and leaving; equals e.n when entering.
  f.ks = schlick(std::min(c, f.cos_t), r0);
  f.kt = 1.0f - f.ks;
  return f;
}

}  // namespace frameless
