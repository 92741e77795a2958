// Binned-SAH builder of the 8-wide BVH over primitive bounds; runs on the loading thread
// (optionally fanning the work out through AccelConfig::parallel_for: the top splits bin in
// parallel chunks, then subtrees are built as parallel tasks). The tree is the same bytes, and
// refs end in the same order, whatever the executor (or none).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/accel/accel_types.h"
#include "core/accel/bvh_node.h"
#include "core/geometry/geometry.h"

namespace frameless {

// Bounds of one primitive; id < num_triangles is a triangle, then spheres up to first_patch,
// then spline patches.
struct PrimRef {
  Vec3 lo{0.0f};
  uint32_t id = 0;
  Vec3 hi{0.0f};
  uint32_t pad = 0;
};

struct Bvh8 {
  std::vector<Bvh8Node> nodes;  // nodes[0] is the root (absent when there are no primitives)
  int depth = 0;                // node levels, root = 1
  size_t leaves = 0;
};

// Builds over refs and leaves refs in leaf order: the triangles of refs (in order) are the
// permuted triangle array, likewise the spheres and patches, and leaf child indices point into
// those arrays. Every leaf holds primitives of one kind only. first_patch defaults to "none".
Bvh8 build_bvh8(std::vector<PrimRef>& refs, uint32_t num_triangles, const AccelConfig& config,
                uint32_t first_patch = 0xffffffffu);
// The same over n references at refs.
Bvh8 build_bvh8(PrimRef* refs, size_t n, uint32_t num_triangles, const AccelConfig& config,
                uint32_t first_patch = 0xffffffffu);

// References allocated without a pass that initialises them (make_prim_refs constructs each
// element once, in parallel when it can), or placed in storage the caller owns.
class PrimRefArray {
 public:
  PrimRefArray() = default;
  explicit PrimRefArray(size_t n);
  // n references at `borrowed` (at least n * sizeof(PrimRef) bytes, kept by the caller).
  PrimRefArray(PrimRef* borrowed, size_t n) : p_(borrowed, Free{false}), n_(n) {}
  PrimRef* data() { return p_.get(); }
  const PrimRef* data() const { return p_.get(); }
  size_t size() const { return n_; }
  PrimRef& operator[](size_t i) { return p_[i]; }
  const PrimRef& operator[](size_t i) const { return p_[i]; }

 private:
  struct Free {
    Free() : owns(true) {}
    explicit Free(bool own) : owns(own) {}
    bool owns;
    void operator()(PrimRef* p) const;
  };
  std::unique_ptr<PrimRef[], Free> p_;
  size_t n_ = 0;
};

// The references of geom's primitives as the BVH build wants them: triangles (the bounds of
// their vertices), then spheres (centre +- |radius|), then spline patches; a primitive whose
// bounds are not finite, or a triangle with a vertex index out of range, gets a point box at the
// origin (its intersection test misses). Filled in parallel chunks through config.parallel_for
// when given and the geometry is large. `into`: storage for them that the caller owns (else
// the array allocates its own).
PrimRefArray make_prim_refs(const Geometry& geom, const AccelConfig& config, PrimRef* into = nullptr);

// Reorders geom's triangles, spheres and patches, with their per-primitive arrays of the same
// length (materials, opposite vertices), into the order build_bvh8 left refs in, which leaf
// indices refer to. Arrays of another length are left alone. In parallel chunks through
// config.parallel_for when given and the geometry is large.
void permute_geometry(Geometry& geom, const PrimRef* refs, size_t n, const AccelConfig& config);

// out[i] <- the three vertices of triangle i (call after permute_geometry: in leaf order); a
// triangle with a vertex index out of range gets NaN corners, which every test misses. In
// parallel chunks like permute_geometry. Storage `out` already has (its capacity) is reused
// whatever it held.
void lay_out_leaf_triangles(const Geometry& geom, const AccelConfig& config, std::vector<LeafTriangle>& out);

// Kind of primitive id: 0 triangle, 1 sphere, 2 patch.
inline int prim_kind(uint32_t id, uint32_t num_triangles, uint32_t first_patch) {
  return id < num_triangles ? 0 : id < first_patch ? 1 : 2;
}
inline uint8_t leaf_kind_bits(int kind) {
  return kind == 0 ? uint8_t(0) : kind == 1 ? kSphereLeafBit : kPatchLeafBit;
}

}  // namespace frameless
