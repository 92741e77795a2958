#include "display/camera_controls.h"

#include <algorithm>
#include <cmath>

namespace frameless {
namespace {

// Rotates v about the unit axis by angle (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& axis, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0f - c);
}

}  // namespace

Camera orbit_camera(const Camera& camera, float dx, float dy, const CameraControlConfig& config) {
  if (!camera_is_valid(camera)) return camera;
  const Vec3 up = glm::normalize(camera.up);
  Vec3 offset = camera.eye - camera.look;
  const float dist = glm::length(offset);
  const float rad = kPi / 180.0f;
  // Yaw about the up axis: dragging right moves the eye to the left around the object.
  offset = rotate(offset, up, -dx * config.orbit_deg_per_pixel * rad);
  // Pitch, clamped so the view direction never becomes parallel to up.
  const float elevation = std::asin(std::clamp(glm::dot(offset / dist, up), -1.0f, 1.0f));
  const float limit = config.max_pitch_deg * rad;
  const float target = std::clamp(elevation + dy * config.orbit_deg_per_pixel * rad, -limit, limit);
  const Vec3 right = glm::normalize(glm::cross(up, offset));
  offset = rotate(offset, right, -(target - elevation));
  Camera out = camera;
  out.eye = camera.look + glm::normalize(offset) * dist;
  return camera_is_valid(out) ? out : camera;
}

Camera pan_camera(const Camera& camera, float dx, float dy, int viewport_height) {
  if (!camera_is_valid(camera) || viewport_height <= 0) return camera;
  const CameraBasis b = make_camera_basis(camera, viewport_height, viewport_height);
  // World units per pixel at the look-at distance.
  const float dist = glm::length(camera.look - camera.eye);
  const float scale = 2.0f * dist * b.tan_half / float(viewport_height);
  const Vec3 shift = (-dx * b.u + dy * b.v) * scale;
  Camera out = camera;
  out.eye += shift;
  out.look += shift;
  return out;
}

Camera zoom_camera(const Camera& camera, float notches, const CameraControlConfig& config) {
  if (!camera_is_valid(camera)) return camera;
  const Vec3 offset = camera.eye - camera.look;
  const float dist = glm::length(offset);
  const float new_dist = std::max(dist * std::pow(config.zoom_per_notch, notches),
                                  config.min_distance);
  Camera out = camera;
  out.eye = camera.look + offset * (new_dist / dist);
  return camera_is_valid(out) ? out : camera;
}

Camera fly_camera(const Camera& camera, float right, float up, float forward, float dt,
                  const CameraControlConfig& config) {
  if (!camera_is_valid(camera)) return camera;
  const CameraBasis b = make_camera_basis(camera, 1, 1);
  const float dist = glm::length(camera.look - camera.eye);
  const float step = config.fly_speed_fraction * dist * dt;
  const Vec3 shift = (right * b.u + up * glm::normalize(camera.up) + forward * b.w) * step;
  Camera out = camera;
  out.eye += shift;
  out.look += shift;
  return out;
}

}  // namespace frameless
