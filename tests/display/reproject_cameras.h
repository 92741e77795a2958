// The reprojection tests' cameras: an eye looking at a point, a 60-degree field of view.
#pragma once
#include "core/scene/camera.h"

namespace frameless {

inline CameraBasis look_at_basis(Vec3 eye, Vec3 look, int width, int height) {
  Camera c;
  c.eye = eye;
  c.look = look;
  c.fov_deg = 60.0f;
  return make_camera_basis(c, width, height);
}

}  // namespace frameless
