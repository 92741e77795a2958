// Bicubic Bézier patches intersected directly (Parker et al. 1999, sec. 3.3): the quadtree of each
// patch's parameter domain becomes a bounding volume hierarchy built bottom-up, and rays are
// intersected with its leaves by Broyden's method. Built on the loading thread; every query is
// const, allocates nothing and is safe from any number of threads.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/types.h"
#include "core/geometry/ray.h"

namespace frameless {

// Bicubic Bézier patch: P(u,v) = sum_i sum_j B_i(v) B_j(u) p[4*i + j] (row i along v, column j
// along u), u, v in [0,1]. The 4 rows of a POV-Ray bicubic_patch map to the rows here, so the
// Utah teapot's normals du x dv point outward (patch_io.h).
struct BezierPatch {
  Vec3 p[16];
};

// Position, and optionally the partial derivatives dP/du, dP/dv (evaluated in double).
Vec3 bezier_eval(const BezierPatch& patch, float u, float v, Vec3* du = nullptr, Vec3* dv = nullptr);

// Unit normal along du x dv. Where the patch is degenerate (an edge collapsed to a point, as at the
// teapot's poles, or du and dv parallel) it is the limit of the normal approaching (u,v) from
// inside the domain; always a finite unit vector, (0,0,1) for a patch collapsed to a point or a
// curve.
Vec3 bezier_normal(const BezierPatch& patch, float u, float v);

// The part of the patch over [u0,u1] x [v0,v1] as a patch of its own (blossoming, in double).
// Pieces cut at the same parameter share their boundary control points bit for bit.
BezierPatch bezier_subpatch(const BezierPatch& patch, float u0, float u1, float v0, float v1);

struct PatchHitStats {
  uint64_t leaf_tests = 0;  // leaf boxes the ray entered
  uint64_t solves = 0;      // Broyden runs started (restarts included; culled leaves not)
  uint64_t converged = 0;   // solves whose residual met the tolerance (accepted or not)
  uint64_t iterations = 0;  // summed over converged solves
};

inline constexpr int kMaxPatchDepth = 8;  // 4^8 = 65536 leaves; bounds the traversal stack

// One surface: the quadtree of the parameter domain subdivided `depth` levels (4^depth leaves), and
// a BVH over it built bottom-up from the subdivided control meshes: a leaf's box is the box of the
// 16 control points of its (overlapped) sub-patch, which contains the sub-patch by the convex hull
// property, grown slightly; a parent's box is the union of its 4 children's.
class PatchSurface {
 public:
  PatchSurface() = default;
  // overlap: fraction of a leaf's parametric extent each leaf domain is widened by on every side
  // (clamped to the patch), so that neighbouring leaves both accept a root on their shared edge.
  // depth is clamped to [0, kMaxPatchDepth] and overlap to [0, 0.5].
  PatchSurface(const BezierPatch& patch, int depth, float overlap = 0.02f);

  Vec3 lo() const;  // bounds of the whole surface
  Vec3 hi() const;

  // Closest hit with t in [tmin, tmax]: returns true and sets t and the patch parameters (u, v)
  // in [0,1]^2. ray.tmin/tmax are not used.
  bool intersect(const Ray& ray, float tmin, float tmax, float& t, float& u, float& v,
                 PatchHitStats* stats = nullptr) const;
  // Any hit with t in [tmin, tmax] (early exit).
  bool occluded(const Ray& ray, float tmin, float tmax) const;

  const BezierPatch& patch() const { return patch_; }
  // Roots nearer than this to a ray's origin are taken for the surface the ray leaves.
  float self_hit_distance() const;
  int depth() const { return depth_; }
  size_t bytes() const;

 private:
  // A node is only its box: the tree is the complete quadtree, stored level by level (level l
  // starts at (4^l - 1) / 3) and in Morton order within a level, so the children of node m are
  // 4m..4m+3 one level down and a leaf's parameter interval follows from its index. The seed
  // stored four doubles per leaf for that interval; here it costs nothing.
  struct Box {
    Vec3 lo, hi;
  };
  template <bool kAny>
  bool traverse(const Ray& ray, float tmin, float tmax, float& t, float& u, float& v,
                PatchHitStats* stats) const;

  BezierPatch patch_{};
  std::vector<Box> boxes_;
  int depth_ = 0;
  float overlap_ = 0.0f;
  float scale_ = 0.0f;  // largest extent of the control points: sets tolerances
};

}  // namespace frameless
