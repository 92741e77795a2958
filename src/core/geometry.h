// Scene geometry as flat arrays (triangles and spheres); built once, read-only while rendering.
#pragma once
#include <vector>

#include "core/types.h"

namespace frameless {

struct Sphere {
  Vec3 center{0.0f};
  float radius = 1.0f;
};

// All primitives of a scene. Primitive id p < num_triangles() is triangle p, otherwise
// sphere p - num_triangles(). The acceleration-structure build may permute the triangle and
// sphere arrays (together with their material arrays) for locality.
struct Geometry {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // per-vertex shading normals: empty, or one per position
  std::vector<UVec3> triangles;
  std::vector<uint16_t> triangle_material;
  std::vector<Sphere> spheres;
  std::vector<uint16_t> sphere_material;

  uint32_t num_triangles() const { return uint32_t(triangles.size()); }
  uint32_t num_spheres() const { return uint32_t(spheres.size()); }
  uint32_t num_primitives() const { return num_triangles() + num_spheres(); }
};

}  // namespace frameless
