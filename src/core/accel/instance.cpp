// Instances of shared meshes: transforms, bounds, and hits carried back to world space.
#include "core/accel/instance.h"

#include <algorithm>
#include <cmath>

#include "core/accel/instance_top.h"

namespace frameless {

bool invert(const Affine& a, Affine& out) {
  out = Affine{};
  const float det = glm::determinant(a.m);
  if (!(std::fabs(det) > 0.0f) || !std::isfinite(det) || !is_finite(a.t)) return false;
  const glm::mat3 inv = glm::inverse(a.m);
  for (int c = 0; c < 3; ++c)
    if (!is_finite(inv[c])) return false;
  out.m = inv;
  out.t = -(inv * a.t);
  return true;
}

bool make_instance(uint32_t mesh, const Affine& to_world, Instance& out) {
  out = Instance{};
  out.mesh = mesh;
  out.to_world = to_world;
  if (!invert(to_world, out.to_object)) return false;
  out.normal_to_world = glm::transpose(out.to_object.m);
  out.stretch = 0.0f;
  for (int c = 0; c < 3; ++c) out.stretch = std::max(out.stretch, glm::length(to_world.m[c]));
  return true;
}

void build_instanced_mesh(InstancedMesh& mesh, const AccelConfig& config) {
  geometry_bounds(mesh.geometry, mesh.lo, mesh.hi);
  mesh.accel.build(mesh.geometry, config);
}

void instance_bounds(const Instance& inst, const InstancedMesh& mesh, Vec3& lo, Vec3& hi) {
  // The eight corners of the object box, transformed: a box that holds the transformed mesh.
  lo = Vec3(kInfinity);
  hi = Vec3(-kInfinity);
  for (int k = 0; k < 8; ++k) {
    const Vec3 c((k & 1) ? mesh.hi.x : mesh.lo.x, (k & 2) ? mesh.hi.y : mesh.lo.y,
                 (k & 4) ? mesh.hi.z : mesh.lo.z);
    const Vec3 w = inst.to_world.point(c);
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
  // Rays are tested in object space after a rounded transform: pad by a relative margin.
  const Vec3 pad = 1e-5f * (glm::abs(lo) + glm::abs(hi)) + Vec3(1e-30f);
  lo -= pad;
  hi += pad;
}

namespace {

// An object-space surface point carried to world space: positions by the affine map, normals
// by the inverse transpose (so a mirrored or non-uniformly scaled instance keeps true normals;
// the facing against the ray is preserved since n.d is invariant under the pair of maps).
SurfacePoint to_world_point(const Instance& inst, const SurfacePoint& o) {
  SurfacePoint sp = o;
  sp.p = inst.to_world.point(o.p);
  sp.ng = unit_or(inst.normal_to_world * o.ng, o.ng);
  sp.ns = unit_or(inst.normal_to_world * o.ns, sp.ng);
  // Rounding of the transformed ray and of the world point both scale with these magnitudes.
  const Vec3 a = glm::abs(sp.p);
  sp.scale = std::max({a.x, a.y, a.z, inst.stretch * o.scale});
  return sp;
}

}  // namespace

SurfacePoint instance_surface_point(const InstanceTop& top, const Ray& ray, const Hit& hit) {
  const Instance& inst = top.instances[hit.inst];
  const InstancedMesh& mesh = *(*top.meshes)[inst.mesh];
  const Ray oray = to_object_ray(inst, ray);
  Hit local = hit;
  local.inst = kInvalidId;
  SurfacePoint sp = to_world_point(inst, surface_point(mesh.geometry, oray, local));
  sp.prim = hit.prim;
  return sp;
}

uint64_t represented_triangles(const Geometry& geom) {
  uint64_t n = geom.num_triangles();
  for (const Instance& i : geom.instances) n += geom.instance_meshes[i.mesh]->triangles();
  return n;
}

}  // namespace frameless
