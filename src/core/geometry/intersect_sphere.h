// Numerically robust ray/sphere intersection (Haines et al., Ray Tracing Gems ch. 7); any thread.
#pragma once
#include <cmath>

#include "core/base/fused_float.h"
#include "core/geometry/geometry.h"
#include "core/geometry/ray.h"

namespace frameless {

// Nearest root of |org + t dir - center| = radius within [tmin, tmax]; a ray starting inside
// finds the far side. The discriminant is formed from the perpendicular offset of the centre
// (no b^2 - ac cancellation for small or distant spheres), and the roots from the stable
// quadratic form (no -b + sqrt(b^2) cancellation).
inline bool intersect_sphere(const Vec3& org, const Vec3& dir, const Sphere& s, float tmin,
                             float tmax, float& t) {
  const Vec3 f = org - s.center;
  // Explicit rounding (core/base/fused_float.h) so every call site returns the same t.
  const float a = dot_exact(dir, dir);
  const float b = dot_exact(f, dir);  // half the linear coefficient
  const float s_b = b / a;
  // l: centre to the line's closest point.
  const Vec3 l{fmadd(-s_b, dir.x, f.x), fmadd(-s_b, dir.y, f.y), fmadd(-s_b, dir.z, f.z)};
  const float r2 = mul_exact(s.radius, s.radius);
  const float disc = mul_exact(a, r2 - dot_exact(l, l));
  if (!(disc >= 0.0f)) return false;
  const float c = dot_exact(f, f) - r2;
  const float q = -(b + std::copysign(std::sqrt(disc), b));
  float t0, t1;
  if (q == 0.0f) {
    t0 = t1 = 0.0f;  // b == 0 and tangent: only when the origin is on the sphere
  } else {
    t0 = c / q;
    t1 = q / a;
    if (t0 > t1) std::swap(t0, t1);
  }
  if (t0 >= tmin && t0 <= tmax) {
    t = t0;
    return true;
  }
  if (t1 >= tmin && t1 <= tmax) {
    t = t1;
    return true;
  }
  return false;
}

}  // namespace frameless
