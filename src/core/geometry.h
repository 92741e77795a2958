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
  std::vector<Vec2> uvs;      // per-vertex texture coordinates: empty, or one per position
  std::vector<UVec3> triangles;
  std::vector<uint16_t> triangle_material;
  // Soft shadows only (empty otherwise): for edge k of each triangle (vertices k, k+1), the
  // vertex of the neighbour across it that is not on the edge, or kInvalidId on an open or
  // non-manifold edge. Neighbours are found by vertex position, so split vertices still join.
  std::vector<UVec3> triangle_opposite;
  std::vector<Sphere> spheres;
  std::vector<uint16_t> sphere_material;

  uint32_t num_triangles() const { return uint32_t(triangles.size()); }
  uint32_t num_spheres() const { return uint32_t(spheres.size()); }
  uint32_t num_primitives() const { return num_triangles() + num_spheres(); }
};

}  // namespace frameless
