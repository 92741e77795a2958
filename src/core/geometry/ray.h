// A ray with a parametric interval [tmin, tmax]; any thread.
#pragma once
#include "core/base/types.h"

namespace frameless {

struct Ray {
  Vec3 org{0.0f};
  float tmin = 0.0f;
  Vec3 dir{0.0f, 0.0f, 1.0f};
  float tmax = kInfinity;
};

// Closest-hit record; prim < num_triangles is a triangle, otherwise sphere (prim - num_triangles).
struct Hit {
  float t = kInfinity;
  uint32_t prim = kInvalidId;
  float u = 0.0f;  // triangle barycentric of vertex 1 (unused for spheres)
  float v = 0.0f;  // triangle barycentric of vertex 2 (unused for spheres)
  uint32_t inst = kInvalidId;  // instance hit (prim then indexes its mesh), or kInvalidId
  bool valid() const { return prim != kInvalidId; }
};

}  // namespace frameless
