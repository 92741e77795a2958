#include "core/scene/camera.h"

#include <cmath>

namespace frameless {

CameraBasis make_camera_basis(const Camera& c, int width, int height) {
  CameraBasis b;
  b.eye = c.eye;
  b.w = glm::normalize(c.look - c.eye);
  b.u = glm::normalize(glm::cross(b.w, c.up));
  b.v = glm::cross(b.u, b.w);
  b.tan_half = std::tan(glm::radians(c.fov_deg) * 0.5f);
  b.width = width;
  b.height = height;
  b.aspect = float(width) / float(height);
  return b;
}

bool camera_is_valid(const Camera& c) {
  if (!is_finite(c.eye) || !is_finite(c.look) || !is_finite(c.up)) return false;
  if (!(c.fov_deg > 0.0f && c.fov_deg < 180.0f)) return false;
  const Vec3 d = c.look - c.eye;
  if (glm::dot(d, d) == 0.0f || glm::dot(c.up, c.up) == 0.0f) return false;
  const Vec3 x = glm::cross(glm::normalize(d), glm::normalize(c.up));
  return glm::dot(x, x) > 1e-12f;
}

}  // namespace frameless
