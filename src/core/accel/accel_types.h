// The acceleration structures' plain types: which structure, build parameters, statistics,
// traversal counters and the cone visitor. What the builders need, apart from the Accel class.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/base/parallel_for.h"
#include "core/base/types.h"
#include "core/geometry/ray.h"

namespace frameless {

// Which acceleration structure a scene uses (seed section 2): the 8-wide BVH, Parker's hybrid
// grid (a uniform grid whose crowded cells hold small BVHs, core/accel/grid_accel.h), or whichever
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
  // Primitives per leaf at most: in trees that outgrow the caches (bvh_build_small.h), where a
  // range of more than a few is a leaf only if the exact SAH of its best split saves rays less
  // than a node visit; in smaller trees, where every range of up to cached_leaf_size is one.
  int max_leaf_size = 16;
  int cached_leaf_size = 4;
  int sah_bins = 16;      // bins per axis for the binned SAH sweep
  // Optional executor for a parallel build: runs body(i) for every i in [0, n), possibly
  // concurrently, and returns when all are done (the caller owns the threads). Empty: serial.
  ParallelFor parallel_for;
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

// Receives the leaves a cone query visits (Accel::visit_cone): primitive ids [first, first +
// count) (triangles below num_triangles, then spheres); returns false to stop early.
class ConeVisitor {
 public:
  virtual bool leaf(uint32_t first, uint32_t count) = 0;

 protected:
  ~ConeVisitor() = default;
};

}  // namespace frameless
