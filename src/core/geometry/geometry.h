// Scene geometry as flat arrays (triangles and spheres); built once, read-only while rendering.
#pragma once
#include <memory>
#include <vector>

#include <glm/mat3x3.hpp>

#include "core/base/types.h"
#include "core/geometry/bezier.h"

namespace frameless {

inline constexpr int kPatchShadowGrid = 6;

struct Sphere {
  Vec3 center{0.0f};
  float radius = 1.0f;
};

// world = m * p + t (column-major glm matrix).
struct Affine {
  glm::mat3 m{1.0f};
  Vec3 t{0.0f};
  Vec3 point(const Vec3& p) const { return m * p + t; }
  Vec3 vector(const Vec3& v) const { return m * v; }
};

// One placement of a shared mesh (core/accel/instance.h).
struct Instance {
  uint32_t mesh = 0;                // index into Geometry::instance_meshes
  Affine to_world;
  Affine to_object;                 // inverse of to_world
  glm::mat3 normal_to_world{1.0f};  // inverse transpose of to_world.m: normals stay normal
  float stretch = 1.0f;             // largest column length of to_world.m: object lengths -> world
};

struct InstancedMesh;

// All primitives of a scene. Primitive id p < num_triangles() is triangle p, then come the
// spheres (p - num_triangles()), then the spline patches (p - num_triangles() - num_spheres()).
// The acceleration-structure build may permute the triangle, sphere and patch arrays (together
// with their material arrays) for locality.
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
  // Bicubic Bézier patches, each with its own bottom-up BVH (seed section 3.3, core/geometry/bezier.h).
  std::vector<PatchSurface> patches;
  std::vector<uint16_t> patch_material;
  // Soft shadows only (empty otherwise): per patch, (kPatchShadowGrid + 1)^2 surface points on a
  // regular (u, v) grid, the occluder the cone query sees (core/shading/soft_shadow.cpp).
  std::vector<Vec3> patch_shadow_grid;
  // Instances of shared meshes (two-level BVH, core/accel/instance.h): the accel permutes instances.
  std::vector<Instance> instances;
  std::vector<std::shared_ptr<InstancedMesh>> instance_meshes;

  uint32_t num_triangles() const { return uint32_t(triangles.size()); }
  uint32_t num_spheres() const { return uint32_t(spheres.size()); }
  uint32_t num_patches() const { return uint32_t(patches.size()); }
  uint32_t first_patch() const { return num_triangles() + num_spheres(); }
  uint32_t num_primitives() const { return num_triangles() + num_spheres() + num_patches(); }
  // Material of primitive `prim` (0 where the kind has no material array).
  uint16_t material_of(uint32_t prim) const {
    const uint32_t nt = num_triangles(), fp = first_patch();
    const std::vector<uint16_t>& m = prim < nt ? triangle_material : prim < fp ? sphere_material : patch_material;
    const uint32_t i = prim < nt ? prim : prim < fp ? prim - nt : prim - fp;
    return i < m.size() ? m[i] : 0;
  }
};

// Bounding box of all geometry (for framing cameras); returns false when empty.
bool geometry_bounds(const Geometry& geom, Vec3& lo, Vec3& hi);

}  // namespace frameless
