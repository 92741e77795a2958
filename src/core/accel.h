// Bounding volume hierarchy over a Geometry: build once, then closest-hit and any-hit queries
// from any number of threads (const, no shared mutable state). Owns no threads.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/ray.h"

namespace frameless {

struct InstanceTop;

// Which acceleration structure a scene uses (seed section 2): the 8-wide BVH, Parker's hybrid
// grid (a uniform grid whose crowded cells hold small BVHs, core/grid_accel.h), or whichever
// does less work on a fixed trial of the scene's own rays (docs/accel.md).
enum class AccelKind : uint8_t { kBvh, kGrid, kAuto };
const char* accel_kind_name(AccelKind k);
bool parse_accel_kind(const std::string& name, AccelKind& out);  // "bvh", "grid" or "auto"

// Work counters of traversals (the auto trial): node visits and primitive tests.
struct TraversalCounts {
  uint64_t nodes = 0;  // BVH: 8-wide nodes entered; grid: cells stepped + cell-BVH nodes
  uint64_t prims = 0;  // primitive tests
};

// Rays per coherent packet (Wald et al. 2001): one AVX2 lane each.
inline constexpr int kPacketSize = 8;

struct AccelConfig {
  AccelKind kind = AccelKind::kBvh;
  float grid_density = 2.0f;    // grid: target cells per primitive
  int grid_bvh_threshold = 16;  // grid: cells with more primitives get their own BVH
  // Auto: the trial's camera rays, and the light positions their hits cast shadow rays to
  // (finalize_scene makes both from the scene's camera and lights). No rays: rays between random
  // points of the scene's box. Read during build only.
  std::vector<Ray> trial_rays;
  std::vector<Vec3> trial_lights;
  int max_leaf_size = 4;  // primitives per leaf at most
  int sah_bins = 16;      // bins per axis for the binned SAH sweep
  // Optional executor for a parallel build: runs body(i) for every i in [0, n), possibly
  // concurrently, and returns when all are done (the caller owns the threads). Empty: serial.
  std::function<void(size_t n, const std::function<void(size_t)>& body)> parallel_for;
};

struct AccelStats {
  double build_ms = 0.0;
  size_t bytes = 0;  // BVH nodes plus any per-primitive data the accel keeps
  size_t nodes = 0;
  size_t leaves = 0;
  int depth = 0;  // node levels, root = 1
  // Geometry arrays the rays read: positions, triangle indices, spheres and material ids (not
  // shading normals). The memory budget applies to bytes + geometry_bytes.
  size_t geometry_bytes = 0;
  AccelKind structure = AccelKind::kBvh;  // the structure in use (never kAuto)
  // Auto only: both structures' build time, memory and weighted work on the trial rays.
  bool trial = false;
  size_t trial_rays = 0;
  double bvh_build_ms = 0, grid_build_ms = 0;
  size_t bvh_bytes = 0, grid_bytes = 0;
  double bvh_cost = 0, grid_cost = 0;
  TraversalCounts bvh_counts, grid_counts;
};

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
  // rays point different ways along an axis, grids and spline patches go ray by ray.
  void intersect_packet(const Ray* rays, int n, Hit* hits, const InstanceTop* top = nullptr) const;
  void occluded_packet(const Ray* rays, int n, bool* occluded, const InstanceTop* top = nullptr) const;
  // The same queries, adding their work to `counts` (the auto trial and bench accel).
  bool intersect_counted(const Ray& ray, Hit& hit, TraversalCounts& counts) const;
  bool occluded_counted(const Ray& ray, TraversalCounts& counts) const;

  // Visits every leaf whose box may meet the cone with apex ray.org, axis ray.dir (unit) and
  // half-angle tangent tan_half, over t in [0, ray.tmax] (soft shadows). Boxes are grown by the
  // cone's radius at their far end, so no primitive inside the cone is missed. The visitor
  // receives primitive ids [first, first + count) (triangles below num_triangles, then spheres)
  // and returns false to stop early. Returns false when stopped.
  class ConeVisitor {
   public:
    virtual bool leaf(uint32_t first, uint32_t count) = 0;

   protected:
    ~ConeVisitor() = default;
  };
  bool visit_cone(const Ray& ray, float tan_half, ConeVisitor& visitor) const;

  // Any hit on instanced geometry only (soft shadows: visit_cone covers the flat geometry, and
  // instances block the shadow ray's axis like a hard shadow).
  bool occluded_instances(const Ray& ray, const InstanceTop* top = nullptr) const;
  bool has_instances() const;
  // The top level built over geom.instances (null without instances); core/instance_top.h.
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
  // The top level over geom.instances (core/accel_instances.cpp).
  void build_instances(Geometry& geom, const AccelConfig& config);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace frameless
