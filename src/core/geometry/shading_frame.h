// An orthonormal frame around a unit vector (Duff et al. 2017, branch-free): soft shadows' cone
// axes and the path tracer's local shading frames. Pure, any thread.
#pragma once
#include <cmath>

#include "core/base/types.h"

namespace frameless {

// to_local(v) = (v.t, v.b, v.n); to_world inverts it.
struct ShadingFrame {
  Vec3 t{1.0f, 0.0f, 0.0f}, b{0.0f, 1.0f, 0.0f}, n{0.0f, 0.0f, 1.0f};
  Vec3 to_local(const Vec3& v) const { return Vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); }
  Vec3 to_world(const Vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

inline ShadingFrame make_shading_frame(const Vec3& n) {
  ShadingFrame f;
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  f.t = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  f.b = Vec3(b, sign + n.y * n.y * a, -n.y);
  f.n = n;
  return f;
}

}  // namespace frameless
