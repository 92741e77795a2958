// Instancing (OpenRT, Wald et al. 2003): a mesh (or sphere set) is stored and built once as a
// bottom-level InstancedMesh with its own BVH, and placed any number of times by Instances, each
// an affine transform; the scene's Accel keeps a top-level BVH over the instances' world boxes
// (core/accel/accel_instances.cpp). Built on one thread, then read-only for render threads.
#pragma once
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/accel/accel.h"
#include "core/geometry/geometry.h"
#include "core/geometry/surface.h"

namespace frameless {

struct Scene;

// The inverse map; false (and identity) when m is singular or not finite.
bool invert(const Affine& a, Affine& out);

// Shared bottom level: geometry in object space, its BVH, and what its cut-out test needs.
struct InstancedMesh {
  std::string name;
  Geometry geometry;
  Accel accel;
  Vec3 lo{0.0f}, hi{0.0f};   // object-space bounds
  // Back to the scene whose materials and textures the cut-out test reads (set by the scene
  // layer's install_alpha_test; the accel only hands it to that test, never reads it).
  const Scene* scene = nullptr;
  uint64_t triangles() const { return geometry.num_triangles(); }
};

// Makes an instance of mesh `mesh` placed by to_world; false when the transform is singular.
bool make_instance(uint32_t mesh, const Affine& to_world, Instance& out);

// Builds a mesh's BVH and bounds (config: the caller's parallel_for, leaf sizes).
void build_instanced_mesh(InstancedMesh& mesh, const AccelConfig& config = {});

// World-space box of an instance.
void instance_bounds(const Instance& inst, const InstancedMesh& mesh, Vec3& lo, Vec3& hi);

// v / |v|, or `fallback` when v has no finite length (normals carried through a transform).
inline Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
  const float len = glm::length(v);
  return len > 0.0f && std::isfinite(len) ? v / len : fallback;
}

// The world ray in the instance's object space: the direction is transformed, not normalized,
// so the ray parameter t means the same point in both spaces.
inline Ray to_object_ray(const Instance& inst, const Ray& ray) {
  Ray r = ray;
  r.org = inst.to_object.point(ray.org);
  r.dir = inst.to_object.vector(ray.dir);
  return r;
}

struct InstanceTop;

// Surface point of a hit on an instance (hit.inst: its position in `top`), in world space.
SurfacePoint instance_surface_point(const InstanceTop& top, const Ray& ray, const Hit& hit);

// Triangles the scene represents: its own plus every instance's mesh.
uint64_t represented_triangles(const Geometry& geom);

}  // namespace frameless
