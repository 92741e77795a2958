// Pinhole camera and its precomputed basis; any thread (pure functions).
#pragma once
#include "core/geometry/ray.h"

namespace frameless {

// User-facing camera: eye, look-at point, up vector, vertical field of view in degrees.
struct Camera {
  Vec3 eye{0.0f, 0.0f, 5.0f};
  Vec3 look{0.0f, 0.0f, 0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float fov_deg = 45.0f;
  bool operator==(const Camera&) const = default;
};

// Precomputed orthonormal basis for an image of width x height pixels.
// Convention: pixel (x, y) has y = 0 at the top row. w = normalize(look - eye),
// u = normalize(w x up), v = u x w, t = tan(fov/2), a = width/height; the ray through
// continuous image position (px, py) has direction
//   normalize(w + (2 px / W - 1) t a u + (1 - 2 py / H) t v);
// with no jitter, pixel (x, y) is sampled at (x + 0.5, y + 0.5).
struct CameraBasis {
  Vec3 eye{0.0f};
  Vec3 u{1.0f, 0.0f, 0.0f};
  Vec3 v{0.0f, 1.0f, 0.0f};
  Vec3 w{0.0f, 0.0f, -1.0f};
  float tan_half = 1.0f;
  float aspect = 1.0f;
  int width = 1;
  int height = 1;
};

CameraBasis make_camera_basis(const Camera& camera, int width, int height);

// Direction through continuous image position (px, py), not normalized: its component along
// the view axis w is 1, so eye + d z is the point at view depth z.
inline Vec3 camera_direction(const CameraBasis& b, float px, float py) {
  const float sx = (2.0f * px / float(b.width) - 1.0f) * b.tan_half * b.aspect;
  const float sy = (1.0f - 2.0f * py / float(b.height)) * b.tan_half;
  return b.w + sx * b.u + sy * b.v;
}

// Primary ray through continuous image position (px, py) in pixel units.
inline Ray camera_ray(const CameraBasis& b, float px, float py) {
  Ray r;
  r.org = b.eye;
  r.dir = glm::normalize(camera_direction(b, px, py));
  return r;
}

// True when the camera can form a basis (finite, eye != look, up not parallel to view, fov in (0,180)).
bool camera_is_valid(const Camera& camera);

}  // namespace frameless
