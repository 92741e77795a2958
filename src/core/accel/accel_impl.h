// Accel's internal state, shared by accel.cpp (BVH build and traversal) and accel_choice.cpp
// (structure choice, grid dispatch); not a public interface.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/accel/accel.h"

#if defined(__AVX2__)
#include <immintrin.h>
#endif
#include "core/accel/bvh_node.h"
#include "core/accel/triangle_block.h"
#include "core/accel/grid_accel.h"
#include "core/accel/robust_far.h"

namespace frameless {

// Levels are bounded by the builder (SAH to depth 32, then medians), each pushes at most 7.
inline constexpr int kStackSize = 512;

// Whether a candidate (t, prim) beats the best hit so far: the nearer, and on an exact tie the
// lower primitive id. The answer depends on no visiting order, so single rays and packets,
// whatever order they walk the tree in, return the same hit bit for bit. Candidates come from
// tests against the widened bound tmax * kRobustFar, which admits every t <= tmax.
inline bool closer_hit(float t, uint32_t prim, bool found, const Hit& best, float ray_tmax) {
  if (!found) return t <= ray_tmax;
  return t < best.t || (t == best.t && prim < best.prim);
}

// Whether a candidate hit on prim survives the cut-out test (always, without cut-outs).
inline bool alpha_opaque(const Accel::AlphaTest& a, const Geometry& g, uint32_t prim,
                         const Ray& ray, float t, float u, float v) {
  return !a.masked_material[g.material_of(prim)] || a.opaque(a.ctx, prim, ray, t, u, v);
}

// Per-ray constants of the slab test.
struct BoxRay {
  Vec3 org;
  Vec3 inv;      // 1 / dir for the entry planes (infinite for zero components)
  Vec3 inv_far;  // 1 / dir widened for the exit planes (see kRobustFar)
  int near[3];   // bounds row of the entry plane per axis (lo when the direction is positive)
};

inline BoxRay make_box_ray(const Ray& ray) {
  BoxRay b;
  b.org = ray.org;
  for (int a = 0; a < 3; ++a) {
    b.inv[a] = 1.0f / ray.dir[a];
    b.inv_far[a] = b.inv[a] * kRobustFar;
    b.near[a] = 2 * a + (std::signbit(ray.dir[a]) ? 1 : 0);
  }
  return b;
}

// Tests the ray against the eight child boxes; returns the mask of boxes entered within
// [tmin, tmax] and their entry distances. A ray parallel to a slab and lying in its boundary
// plane gives 0 * inf = NaN for that slab; min/max take the accumulator (second operand of
// maxps/minps) then, so the slab is ignored and the boundary counts as inside.
inline uint32_t intersect_children(const Bvh8Node& n, const BoxRay& r, float tmin, float tmax,
                                   float* dist) {
#if defined(__AVX2__)
  const __m256 ox = _mm256_set1_ps(r.org.x), oy = _mm256_set1_ps(r.org.y),
               oz = _mm256_set1_ps(r.org.z);
  const __m256 tnx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[r.near[0]]), ox),
                                   _mm256_set1_ps(r.inv.x));
  const __m256 tny = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[r.near[1]]), oy),
                                   _mm256_set1_ps(r.inv.y));
  const __m256 tnz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[r.near[2]]), oz),
                                   _mm256_set1_ps(r.inv.z));
  const __m256 tfx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[r.near[0] ^ 1]), ox),
                                   _mm256_set1_ps(r.inv_far.x));
  const __m256 tfy = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[r.near[1] ^ 1]), oy),
                                   _mm256_set1_ps(r.inv_far.y));
  const __m256 tfz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(n.bounds[r.near[2] ^ 1]), oz),
                                   _mm256_set1_ps(r.inv_far.z));
  const __m256 tn =
      _mm256_max_ps(tnx, _mm256_max_ps(tny, _mm256_max_ps(tnz, _mm256_set1_ps(tmin))));
  const __m256 tf =
      _mm256_min_ps(tfx, _mm256_min_ps(tfy, _mm256_min_ps(tfz, _mm256_set1_ps(tmax))));
  _mm256_store_ps(dist, tn);
  return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)));
#else
  uint32_t mask = 0;
  for (int i = 0; i < kBvhWidth; ++i) {
    float tn = tmin, tf = tmax;
    for (int a = 0; a < 3; ++a) {
      tn = std::max(tn, (n.bounds[r.near[a]][i] - r.org[a]) * r.inv[a]);  // NaN keeps tn
      tf = std::min(tf, (n.bounds[r.near[a] ^ 1][i] - r.org[a]) * r.inv_far[a]);
    }
    dist[i] = tn;
    mask |= uint32_t(tn <= tf) << i;
  }
  return mask;
#endif
}

// The root's children the ray enters and their entry distances, tested before a walk's set-up:
// a ray missing the whole tree (many camera rays; a third of the rays that enter an instance's
// world box miss its mesh) then never pays for it, and the walk starts from this test.
struct RootTest {
  alignas(32) float dist[kBvhWidth];
  uint32_t mask = 0;
};

inline RootTest test_root(const std::vector<Bvh8Node>& nodes, const BoxRay& br, const Ray& ray) {
  RootTest r;
  if (!nodes.empty()) r.mask = intersect_children(nodes[0], br, ray.tmin, ray.tmax * kRobustFar, r.dist);
  return r;
}

// Puts x onto the stack above `base` kept far to near (the nearest on top, popped first); x goes
// below the entries as near or nearer, so ties are walked in slot order. Walks push a node's
// entered children this way, in place: a copy through a scratch array became a memcpy call.
template <class Entry>
inline void push_far_to_near(Entry* stack, int base, int& sp, const Entry& x) {
  int k = sp++;
  while (k > base && stack[k - 1].t <= x.t) stack[k] = stack[k - 1], --k;
  stack[k] = x;
}

// Asks for the cache lines of [begin, begin + bytes).
inline void prefetch_lines(const void* begin, size_t bytes) {
  const uintptr_t end = reinterpret_cast<uintptr_t>(begin) + bytes;
  for (uintptr_t line = reinterpret_cast<uintptr_t>(begin) & ~uintptr_t(63); line < end; line += 64)
    __builtin_prefetch(reinterpret_cast<const void*>(line));
}

// Asks for child j of `node`, so its fetch overlaps the rest of the node's work: a node's four
// lines (and its triangle block, given the blocks), or a leaf's triangles (or spheres, given
// them) whole: leaves hold up to 16 (AccelConfig::max_leaf_size), nine lines of triangles.
inline void prefetch_child(const Bvh8Node* nodes, const LeafTriangle* leaf_tris, const Bvh8Node& node, int j,
                           const TriangleBlock* blocks = nullptr, const Sphere* spheres = nullptr) {
  const uint8_t info = node.info[j];
  if (info == 0) {
    const char* a = reinterpret_cast<const char*>(nodes + node.child[j]);
    for (int line = 0; line < 4; ++line) __builtin_prefetch(a + 64 * line);
    if (blocks && (node.blocked >> j & 1u))  // and its single-triangle leaves
      prefetch_block(blocks + node.child_blocks + uint32_t(__builtin_popcount(node.blocked & ((1u << j) - 1u))));
  } else if (!(info & (kPatchLeafBit | kSphereLeafBit))) {
    prefetch_lines(leaf_tris + node.child[j], sizeof(LeafTriangle) * info);
  } else if (spheres && (info & kSphereLeafBit)) {
    prefetch_lines(spheres + node.child[j], sizeof(Sphere) * (info & kLeafCountMask));
  }
}

struct Accel::Impl {
  const Geometry* geom = nullptr;
  std::vector<Bvh8Node> nodes;     // the BVH (empty when the grid is in use)
  std::vector<LeafTriangle> leaf_tris;  // by triangle index (leaf order), with the BVH
  std::vector<TriangleBlock> blocks;    // nodes' single-triangle leaves side by side, with the BVH
  bool lane_tests = true;               // leaves of two or more triangles tested in lanes
  bool prefetch = true;                 // walks ask for entered children ahead (prefetch_policy.h)
  std::unique_ptr<GridAccel> grid;  // the hybrid grid, when chosen
  AccelStats stats;
  AlphaTest alpha;  // opaque == nullptr: no cut-out surfaces
  std::shared_ptr<const InstanceTop> top;  // top level over geom->instances (null: none)
  float scene_size = 0.0f;     // largest extent of the root box (packets' coherence test)
  // Vertex and sphere storage already moved to huge pages (a rebuild does not copy it again).
  const void* homed_positions = nullptr;
  const void* homed_spheres = nullptr;
};

}  // namespace frameless
