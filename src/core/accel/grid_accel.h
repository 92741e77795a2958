// The hybrid grid of Parker et al. 1999 (sec. 2): a uniform grid walked with a 3-D DDA
// (Amanatides & Woo 1987, Fujimoto 1986) whose crowded cells hold a small binary BVH instead of a
// list. Build once (loading thread), then closest-hit, any-hit and cone queries from any number of
// threads (const, no shared mutable state). An alternative to the 8-wide BVH (Accel).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/accel/accel_types.h"
#include "core/geometry/geometry.h"
#include "core/geometry/ray.h"

namespace frameless {

struct GridConfig {
  // Target cells per primitive: cells per axis = extent * cbrt(density * N / volume) (Cleary and
  // Wyvill 1988), over the axes that are not flat, then clamped.
  float density = 2.0f;
  int bvh_threshold = 16;              // cells with more primitives get their own small BVH
  int max_resolution = 1024;           // cells per axis at most (4096 at most)
  size_t max_cells = size_t(1) << 25;  // cells in all at most (2^30 at most; 4 bytes each)
};

struct GridStats {
  double build_ms = 0;
  size_t bytes = 0;  // cell offsets + occupancy bits + primitive ids + cell-BVH nodes (no geometry)
  int res[3] = {0, 0, 0};
  size_t cells = 0, nonempty = 0, refs = 0, cell_bvhs = 0;
};

// TraversalCounts (core/accel/accel.h): nodes are cells stepped plus cell-BVH nodes visited.

// Primitive ids as in Geometry: triangles, then spheres, then spline patches.
class GridAccel {
 public:
  // Builds over geom without permuting it; geom must outlive the grid (and not change).
  // Primitives with non-finite bounds or bad vertex indices are left out: no ray hits them.
  // Cells take every primitive whose bounding box overlaps them (no triangle-box test).
  void build(const Geometry& geom, const GridConfig& config = {});

  // Closest hit in [ray.tmin, ray.tmax]; fills hit and returns true when found. counts, when
  // given, is added to (both queries).
  bool intersect(const Ray& ray, Hit& hit, TraversalCounts* counts = nullptr) const;
  // Any hit in [ray.tmin, ray.tmax] (early exit): for shadow rays.
  bool occluded(const Ray& ray, TraversalCounts* counts = nullptr) const;
  // Accel::visit_cone's contract: calls visitor.leaf(id, 1) for every primitive that may meet the
  // cone (apex ray.org, unit axis ray.dir, half-angle tangent tan_half, t in [0, ray.tmax]). A
  // primitive in several cells may be reported more than once (a small mailbox removes most
  // repeats). Returns false when the visitor stopped.
  bool visit_cone(const Ray& ray, float tan_half, ConeVisitor& visitor) const;

  const GridStats& stats() const { return stats_; }

  // Node of a cell's BVH (DFS order): count == 0 is an inner node whose left child follows it and
  // whose right child is nodes[index]; otherwise a leaf of ids[index, index + count).
  struct Node {
    Vec3 lo;
    uint32_t index;
    Vec3 hi;
    uint32_t count;
  };

 private:
  template <bool kAnyHit>
  bool traverse(const Ray& ray, Hit& hit, TraversalCounts* counts) const;

  const Geometry* geom_ = nullptr;
  Vec3 lo_{0.0f}, hi_{0.0f};  // grid box (padded primitive bounds)
  Vec3 cell_{1.0f}, inv_cell_{1.0f};
  float pad_ = 0.0f;  // cells take primitives whose bounds come this close (rounding margin)
  int res_[3] = {0, 0, 0};
  uint32_t list_max_ = 16;  // a cell with more ids than this starts with its BVH root index
  // CSR layout: cell c holds ids_[offsets_[c], offsets_[c + 1]), x fastest.
  std::vector<uint32_t> offsets_;
  std::vector<uint32_t> ids_;
  std::vector<uint64_t> occupied_;  // one bit per cell: non-empty
  std::vector<Node> nodes_;
  GridStats stats_;
};

}  // namespace frameless
