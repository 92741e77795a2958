// Bounding volume hierarchy over a Geometry: build once, then closest-hit and any-hit queries
// from any number of threads (const, no shared mutable state). Owns no threads.
#pragma once
#include <memory>

#include "core/accel/accel_types.h"
#include "core/geometry/geometry.h"
#include "core/geometry/ray.h"

namespace frameless {

struct InstanceTop;

class Accel {
 public:
  Accel();
  ~Accel();
  Accel(Accel&&) noexcept;
  Accel& operator=(Accel&&) noexcept;

  // Builds over geom; may permute geom's primitive arrays. geom must outlive the Accel.
  void build(Geometry& geom, const AccelConfig& config = {});

  // Closest hit in [ray.tmin, ray.tmax]; fills hit and returns true when found. `top`: the
  // instances' top level to use instead of the one built here (instances moved since; null:
  // the built one); hit.inst is a position in the top in use.
  bool intersect(const Ray& ray, Hit& hit, const InstanceTop* top = nullptr) const;
  // Any hit in [ray.tmin, ray.tmax] (early exit): for shadow rays.
  bool occluded(const Ray& ray, const InstanceTop* top = nullptr) const;
  // The same queries for n <= kPacketSize rays traced together through the tree (coherent
  // packets: neighbouring camera rays, or shadow rays from neighbouring points). Each result is
  // bit for bit what the single-ray query returns; hits[i] is reset on a miss. Packets whose
  // rays point different ways along an axis, grids and spline patches go ray by ray; instances'
  // top level is walked by the packet's rays together, each instance's mesh ray by ray.
  void intersect_packet(const Ray* rays, int n, Hit* hits, const InstanceTop* top = nullptr) const;
  void occluded_packet(const Ray* rays, int n, bool* occluded, const InstanceTop* top = nullptr) const;
  // The same queries, adding their work to `counts` (the auto trial and bench accel).
  bool intersect_counted(const Ray& ray, Hit& hit, TraversalCounts& counts) const;
  bool occluded_counted(const Ray& ray, TraversalCounts& counts) const;

  // Visits every leaf whose box may meet the cone with apex ray.org, axis ray.dir (unit) and
  // half-angle tangent tan_half, over t in [0, ray.tmax] (soft shadows). Boxes are grown by the
  // cone's radius at their far end, so no primitive inside the cone is missed. The visitor
  // gets the leaves (core/accel/accel_types.h). Returns false when stopped.
  using ConeVisitor = frameless::ConeVisitor;
  bool visit_cone(const Ray& ray, float tan_half, ConeVisitor& visitor) const;

  // Any hit on instanced geometry only (soft shadows: visit_cone covers the flat geometry, and
  // instances block the shadow ray's axis like a hard shadow).
  bool occluded_instances(const Ray& ray, const InstanceTop* top = nullptr) const;
  bool has_instances() const;
  // The top level built over geom.instances (null without instances); core/accel/instance_top.h.
  std::shared_ptr<const InstanceTop> instance_top() const;
  // `top` when given, else the built one (null without instances).
  const InstanceTop* top_in_use(const InstanceTop* top) const;

  // Cut-out surfaces: when set, a candidate hit on a primitive for which masked(prim) is true is
  // kept only if opaque(ctx, prim, ray, t, u, v) says so (alpha textures). Empty: no test at all.
  struct AlphaTest {
    const void* ctx = nullptr;
    const uint8_t* masked_material = nullptr;  // one flag per material id
    bool (*opaque)(const void* ctx, uint32_t prim, const Ray& ray, float t, float u, float v) =
        nullptr;
  };
  void set_alpha_test(const AlphaTest& test);

  const AccelStats& stats() const;

 private:
  void build_bvh(Geometry& geom, const AccelConfig& config);
  // The top level over geom.instances (core/accel/accel_instances.cpp).
  void build_instances(Geometry& geom, const AccelConfig& config);
  // One ray's walk of the BVH (accel.cpp): the root's test, then the walk that suits the ray and
  // the geometry.
  template <bool kAnyHit>
  bool walk_tree(const Ray& ray, Hit& hit) const;
  // The queries on the flat geometry only (BVH or grid, no instances): packets that go ray by
  // ray below a shared walk of the instances (accel_packet.cpp).
  bool intersect_flat(const Ray& ray, Hit& hit) const;
  bool occluded_flat(const Ray& ray) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace frameless
