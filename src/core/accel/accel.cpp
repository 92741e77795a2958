// The 8-wide BVH: build (bvh_build.cpp) plus ordered closest-hit and early-exit any-hit traversal
// with one AVX2 box test per node.
#include "core/accel/accel.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <type_traits>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "core/accel/accel_impl.h"
#include "core/accel/bvh_build.h"
#include "core/accel/bvh_build_spheres.h"
#include "core/accel/fused_slab.h"
#include "core/accel/instance_top.h"
#include "core/accel/prefetch_policy.h"
#include "core/base/huge_pages.h"
#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"

namespace frameless {
namespace {

struct StackEntry {
  uint32_t ref;
  uint32_t info;
  float t;
};

}  // namespace

Accel::Accel() : impl_(std::make_unique<Impl>()) {}
Accel::~Accel() = default;
Accel::Accel(Accel&&) noexcept = default;
Accel& Accel::operator=(Accel&&) noexcept = default;

void Accel::build_bvh(Geometry& geom, const AccelConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  Impl& im = *impl_;
  im.geom = &geom;
  std::vector<Bvh8Node>().swap(im.nodes);  // a rebuild must not hold two trees at its peak
  // Rays fetch vertices and spheres at random: their storage goes to huge pages, once.
  const auto home = [](auto& v, const void*& homed) {
    if (v.data() == homed) return;
    rehome_huge(v);
    homed = v.data();
  };
  home(geom.positions, im.homed_positions);
  Bvh8 bvh;
  if (geom.num_triangles() == 0 && geom.num_patches() == 0) {
    // Sphere-only geometry: built in place (a sphere is its own bounds), no reference array.
    home(geom.spheres, im.homed_spheres);
    bvh = build_bvh8_spheres(geom.spheres, geom.sphere_material, config);
  } else {
    // References and the leaf-order permutation in parallel chunks, bit for bit the serial
    // result (bvh_build.h); primitives are stored in leaf order, so a leaf is a contiguous run.
    const uint32_t nt = geom.num_triangles(), ns = geom.num_spheres();
    // A mesh's references live in the pages its leaf triangles then take (36 bytes a triangle
    // against 32 a reference): a fresh page costs more than its bytes to the kernel that clears
    // it (benchmarks.md, section 35), and the references are dead once the geometry is permuted.
    static_assert(sizeof(LeafTriangle) >= sizeof(PrimRef), "a triangle's storage holds its reference");
    std::vector<LeafTriangle>().swap(im.leaf_tris);
    PrimRef* into = nullptr;
    if (ns == 0 && geom.num_patches() == 0) {
      resize_huge(im.leaf_tris, nt);  // LeafTriangle() writes nothing: no page is touched yet
      into = reinterpret_cast<PrimRef*>(im.leaf_tris.data());
    }
    PrimRefArray refs = make_prim_refs(geom, config, into);
    bvh = build_bvh8(refs.data(), refs.size(), nt, config, nt + ns);
    permute_geometry(geom, refs.data(), refs.size(), config);
  }
  if (bvh.depth * (kBvhWidth - 1) + 1 > kStackSize) {
    std::fprintf(stderr, "frameless: accel: BVH depth %d exceeds the traversal stack\n", bvh.depth);
    std::abort();
  }
  im.nodes = std::move(bvh.nodes);
  lay_out_leaf_triangles(geom, config, im.leaf_tris);  // after the permutation: in leaf order
  im.blocks = lay_out_triangle_blocks(im.nodes, im.leaf_tris, config);
  im.lane_tests = triangle_lanes_wanted();
  im.prefetch = prefetch_wanted(im.nodes.size() * sizeof(Bvh8Node) + im.leaf_tris.size() * sizeof(LeafTriangle) +
                                im.blocks.size() * sizeof(TriangleBlock));
  im.scene_size = 0.0f;  // the root box's largest extent: the union of its children
  if (!im.nodes.empty())
    for (int a = 0; a < 3; ++a) {
      float lo = kInfinity, hi = -kInfinity;
      for (int i = 0; i < kBvhWidth; ++i)
        if (im.nodes[0].bounds[2 * a][i] <= im.nodes[0].bounds[2 * a + 1][i])
          lo = std::min(lo, im.nodes[0].bounds[2 * a][i]), hi = std::max(hi, im.nodes[0].bounds[2 * a + 1][i]);
      if (std::isfinite(hi - lo)) im.scene_size = std::max(im.scene_size, hi - lo);
    }

  AccelStats& s = im.stats;
  s = {};
  s.nodes = im.nodes.size();
  s.leaves = bvh.leaves;
  s.depth = bvh.depth;
  s.bytes = im.nodes.size() * sizeof(Bvh8Node) + im.leaf_tris.size() * sizeof(LeafTriangle) +
            im.blocks.size() * sizeof(TriangleBlock);
  s.geometry_bytes = geom.positions.size() * sizeof(Vec3) + geom.triangles.size() * sizeof(UVec3) +
                     geom.triangle_material.size() * sizeof(uint16_t) +
                     geom.spheres.size() * sizeof(Sphere) +
                     geom.sphere_material.size() * sizeof(uint16_t) +
                     geom.patch_material.size() * sizeof(uint16_t);
  for (const PatchSurface& p : geom.patches) s.geometry_bytes += p.bytes();
  build_instances(geom, config);
  s.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

namespace {

// kTriangles: the geometry has triangles only and no cut-outs, so the sphere, patch and cut-out
// paths are compiled out and the loop makes no call (its constants can stay in registers).
// kFused: the nodes are tested in the fused form (fused_slab.h), which the ray must admit.
template <bool kAnyHit, bool kCount = false, bool kTriangles = false, bool kFused = false>
bool traverse(const std::vector<Bvh8Node>& node_array, const LeafTriangle* leaf_tris,
              const TriangleBlock* blocks, bool lane_tests, bool prefetch, const Geometry& g, const Ray& ray,
              const BoxRay& br, const RootTest& root, Hit& hit, const Accel::AlphaTest& alpha,
              TraversalCounts* counts = nullptr) {
  if (node_array.empty()) return false;
  const Bvh8Node* nodes = node_array.data();
  const Sphere* spheres = g.spheres.data();
  const uint32_t num_tris = g.num_triangles();
#if defined(__AVX2__)
  FusedSlab fused;
  if constexpr (kFused) fused = make_fused_slab(br);
#endif
  // The shear set-up (two divisions, the lanes' constants) waits for the first triangle test: a
  // ray through an instance's box often leaves the mesh without one, and sphere-only scenes
  // never need it.
  TriangleRay tr;
  bool tr_ready = false;
  const float tmin = ray.tmin;
  float tmax = ray.tmax;
  // Box entry distances carry rounding error too: compare them against a widened tmax, or a box
  // whose primitive ties with the current hit within an ulp would be culled.
  float tmax_box = tmax * kRobustFar;
  bool found = false;
  // A closer hit shrinks the interval every later box and primitive is tested against.
  auto record = [&](float t, float u, float v, uint32_t prim) {
    tmax = t;
    tmax_box = t * kRobustFar;
    hit.t = t;
    hit.u = u;
    hit.v = v;
    hit.prim = prim;
    hit.inst = kInvalidId;
    found = true;
  };
  // A triangle's hit within the widened interval: kept when it beats the best (closest hit),
  // and not cut out. True when an any-hit walk is done.
  auto candidate = [&](float t, float u, float v, uint32_t prim) {
    if (!(kAnyHit ? t <= tmax : closer_hit(t, prim, found, hit, ray.tmax))) return false;
    if (!kTriangles && alpha.opaque && !alpha_opaque(alpha, g, prim, ray, t, u, v)) return false;
    if constexpr (kAnyHit) return true;
    record(t, u, v, prim);
    return false;
  };
#if defined(__AVX2__)
  BlockRay block_ray;
#endif
  const auto shear = [&] {
    if (__builtin_expect(tr_ready, 1)) return;
    tr = make_triangle_ray(ray);
#if defined(__AVX2__)
    block_ray = BlockRay(tr);
#endif
    tr_ready = true;
  };
#if defined(__AVX2__)
  // The lanes `lanes` of q, lane i holding triangle prim(i) (lanes exactly on an edge go to the
  // scalar test, which decides them in double); true when an any-hit walk is done.
  const auto test_lanes = [&](const auto& source, uint32_t lanes, auto prim) {
    __m256 tv = _mm256_setzero_ps(), uv = tv, vv = tv;
    uint32_t redo = 0;
    uint32_t hits = lane_hits(source, block_ray, lanes, tmin, tmax_box, tv, uv, vv, redo);
    if (!(hits | redo)) return false;
    alignas(32) float ts[kBvhWidth], us[kBvhWidth], vs[kBvhWidth];
    if (hits) _mm256_store_ps(ts, tv), _mm256_store_ps(us, uv), _mm256_store_ps(vs, vv);
    for (uint32_t m = redo; m; m &= m - 1) {
      const int i = __builtin_ctz(m);
      const LeafTriangle& tri = leaf_tris[prim(i)];
      if (intersect_triangle(tr, tri.p[0], tri.p[1], tri.p[2], tmin, tmax_box, ts[i], us[i], vs[i])) hits |= 1u << i;
    }
    for (; hits; hits &= hits - 1) {
      const int i = __builtin_ctz(hits);
      if (candidate(ts[i], us[i], vs[i], prim(i))) return true;
    }
    return false;
  };
#endif

  StackEntry stack[kStackSize];
  int sp = 0;
  uint32_t ref = 0, info = 0;  // start at the root node
  for (;;) {
    if (info == 0) {
      const Bvh8Node& node = nodes[ref];
      if constexpr (kCount) ++counts->nodes;
      alignas(32) float dist[kBvhWidth];
      uint32_t mask;
      if (__builtin_expect(ref == 0, 0)) {  // the root, tested by the caller with this tmax
        mask = root.mask;
        std::memcpy(dist, root.dist, sizeof dist);
      } else {
#if defined(__AVX2__)
        if constexpr (kFused)
          mask = fused_children(node, fused, tmin, tmax_box, dist);
        else
#endif
          mask = intersect_children(node, br, tmin, tmax_box, dist);
      }
      // Every entered child is asked for now, so its fetch overlaps this node's work and the
      // siblings' (incoherent rays wait on each node and leaf in turn otherwise), in a tree too
      // big for the cache.
      if (prefetch)
        for (uint32_t m = mask & ~uint32_t(node.singles); m; m &= m - 1)
          prefetch_child(nodes, leaf_tris, node, __builtin_ctz(m), blocks, spheres);
#if defined(__AVX2__)
      if (const uint32_t singles = mask & node.singles) {
        // The single-triangle leaves entered, all in one pass (the rest of the node as usual).
        mask &= ~singles;
        if constexpr (kCount) counts->prims += uint64_t(__builtin_popcount(singles));
        const float before = tmax_box;
        shear();
        if (test_lanes(block_source(blocks[node.block], block_ray), singles, [&](int i) { return node.child[i]; }))
          return true;
        // A nearer hit: boxes that start beyond it are left out.
        if (tmax_box < before && mask)
          mask &= uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_load_ps(dist), _mm256_set1_ps(tmax_box), _CMP_LE_OQ)));
      }
#endif
      if (mask != 0) {
        uint32_t i = uint32_t(__builtin_ctz(mask));
        mask &= mask - 1;
        if (mask == 0) {  // one child entered: descend without touching the stack
          ref = node.child[i];
          info = node.info[i];
          continue;
        }
        if constexpr (kAnyHit) {
          // Any hit ends the walk: descend into the nearest box (the likeliest to block), push the rest.
          uint32_t near = i;
          for (uint32_t m = mask; m; m &= m - 1)
            if (dist[__builtin_ctz(m)] < dist[near]) near = uint32_t(__builtin_ctz(m));
          mask = (mask | 1u << i) & ~(1u << near);  // the entered children but the nearest
          do {
            const uint32_t j = uint32_t(__builtin_ctz(mask));
            stack[sp++] = {node.child[j], node.info[j], dist[j]};
            mask &= mask - 1;
          } while (mask);
          ref = node.child[near];
          info = node.info[near];
          continue;
        } else {
          // Two or more: onto the stack far to near, then the nearest is popped and walked.
          const int base = sp;
          stack[sp++] = {node.child[i], node.info[i], dist[i]};
          do {
            const uint32_t j = uint32_t(__builtin_ctz(mask));
            push_far_to_near(stack, base, sp, StackEntry{node.child[j], node.info[j], dist[j]});
            mask &= mask - 1;
          } while (mask);
          --sp;
          ref = stack[sp].ref;
          info = stack[sp].info;
          continue;
        }
      }
    } else if (!kTriangles && (info & kPatchLeafBit)) {
      // Spline patches: each walks its own bottom-up BVH to Broyden's method (core/geometry/bezier.h).
      const uint32_t count = info & kLeafCountMask, first = g.first_patch();
      if constexpr (kCount) counts->prims += count;
      for (uint32_t k = 0; k < count; ++k) {
        const PatchSurface& ps = g.patches[ref + k];
        if constexpr (kAnyHit) {
          if (!alpha.opaque) {
            if (ps.occluded(ray, tmin, tmax)) return true;
            continue;
          }
        }
        float t, u, v;
        if (ps.intersect(ray, tmin, tmax, t, u, v)) {
          if (alpha.opaque && !alpha_opaque(alpha, g, first + ref + k, ray, t, u, v)) continue;
          if constexpr (kAnyHit) return true;
          record(t, u, v, first + ref + k);
        }
      }
    } else if (!kTriangles && (info & kSphereLeafBit)) {
      const uint32_t count = info & kLeafCountMask;
      if constexpr (kCount) counts->prims += count;
      for (uint32_t k = 0; k < count; ++k) {
        float t;
        const uint32_t prim = num_tris + ref + k;
        if (intersect_sphere(ray.org, ray.dir, spheres[ref + k], tmin, tmax_box, t) &&
            (kAnyHit ? t <= tmax : closer_hit(t, prim, found, hit, ray.tmax))) {
          if (alpha.opaque && !alpha_opaque(alpha, g, prim, ray, t, 0.0f, 0.0f)) continue;
          if constexpr (kAnyHit) return true;
          record(t, 0.0f, 0.0f, prim);
        }
      }
    } else {
      if constexpr (kCount) counts->prims += info;
      uint32_t k = 0;
      shear();
#if defined(__AVX2__)
      // Two or more triangles: up to four at a time in one pass of the lanes' test.
      if (lane_tests)
        for (; k + 1 < info; k += 4) {
          const uint32_t first = ref + k, n = std::min<uint32_t>(info - k, 4);
          if (test_lanes(leaf_source(leaf_tris + first, n, block_ray), (1u << n) - 1u,
                         [&](int i) { return first + uint32_t(i); }))
            return true;
        }
#else
      (void)lane_tests;
#endif
      for (; k < info; ++k) {
        const LeafTriangle& tri = leaf_tris[ref + k];
        float t, u, v;
        if (intersect_triangle(tr, tri.p[0], tri.p[1], tri.p[2], tmin, tmax_box, t, u, v) &&
            candidate(t, u, v, ref + k))
          return true;
      }
    }
    // Pop the nearest pending entry that may still hold a closer hit.
    for (;;) {
      if (sp == 0) return found;
      const StackEntry& e = stack[--sp];
      if (e.t <= tmax_box) {
        ref = e.ref;
        info = e.info;
        break;
      }
    }
  }
}

// The walk for the ray and the geometry: triangle-only or general, fused or today's slab test.
template <bool kAnyHit, class Walk>
bool walk_for(const Geometry& g, const Accel::AlphaTest& alpha, const Ray& ray, const Walk& walk) {
  const bool triangles = !alpha.opaque && g.spheres.empty() && g.patches.empty();
  using T = std::true_type;
  using F = std::false_type;
#if defined(__AVX2__)
  if (fused_slab_applies(ray)) return triangles ? walk(T(), T()) : walk(F(), T());
#endif
  return triangles ? walk(T(), F()) : walk(F(), F());
}

}  // namespace

template <bool kAnyHit>
bool Accel::walk_tree(const Ray& ray, Hit& hit) const {
  const Impl& im = *impl_;
  const BoxRay br = make_box_ray(ray);
  const RootTest root = test_root(im.nodes, br, ray);
  if (!root.mask) return false;
  return walk_for<kAnyHit>(*im.geom, im.alpha, ray, [&](auto triangles, auto fused) {
    return traverse<kAnyHit, false, decltype(triangles)::value, decltype(fused)::value>(
        im.nodes, im.leaf_tris.data(), im.blocks.data(), im.lane_tests, im.prefetch, *im.geom, ray, br, root, hit,
        im.alpha);
  });
}

bool Accel::intersect_flat(const Ray& ray, Hit& hit) const {
  hit.inst = kInvalidId;  // a hit found here is on flat geometry
  if (impl_->grid) return impl_->grid->intersect(ray, hit);
  return impl_->geom && walk_tree<false>(ray, hit);
}

bool Accel::occluded_flat(const Ray& ray) const {
  if (impl_->grid) return impl_->grid->occluded(ray);
  Hit unused;
  return impl_->geom && walk_tree<true>(ray, unused);
}

// The flat walks written out again below rather than calling the flat queries: with the calls
// the bunny's single shadow rays measured 0.93x (faster in 0 of 6 alternating rounds).
bool Accel::intersect(const Ray& ray, Hit& hit, const InstanceTop* top) const {
  hit.inst = kInvalidId;  // a hit found below is on flat geometry unless an instance says so
  bool found;
  if (impl_->grid)
    found = impl_->grid->intersect(ray, hit);
  else
    found = impl_->geom && walk_tree<false>(ray, hit);
  // Instances after the flat geometry, within its closest hit (both orders give one answer).
  if ((top = top_in_use(top))) found = intersect_instances(*top, ray, hit, found);
  return found;
}

bool Accel::occluded(const Ray& ray, const InstanceTop* top) const {
  if (impl_->grid) return impl_->grid->occluded(ray) || occluded_instances(ray, top);
  Hit unused;
  if (impl_->geom && walk_tree<true>(ray, unused)) return true;
  return occluded_instances(ray, top);
}

bool Accel::intersect_counted(const Ray& ray, Hit& hit, TraversalCounts& counts) const {
  if (impl_->grid) return impl_->grid->intersect(ray, hit, &counts);
  const BoxRay br = make_box_ray(ray);
  return impl_->geom &&
         traverse<false, true>(impl_->nodes, impl_->leaf_tris.data(), impl_->blocks.data(), impl_->lane_tests, impl_->prefetch, *impl_->geom, ray, br, test_root(impl_->nodes, br, ray), hit, impl_->alpha, &counts);
}

bool Accel::occluded_counted(const Ray& ray, TraversalCounts& counts) const {
  if (impl_->grid) return impl_->grid->occluded(ray, &counts);
  Hit unused;
  const BoxRay br = make_box_ray(ray);
  return impl_->geom &&
         traverse<true, true>(impl_->nodes, impl_->leaf_tris.data(), impl_->blocks.data(), impl_->lane_tests, impl_->prefetch, *impl_->geom, ray, br, test_root(impl_->nodes, br, ray), unused, impl_->alpha, &counts);
}

void Accel::set_alpha_test(const AlphaTest& test) { impl_->alpha = test; }

const AccelStats& Accel::stats() const { return impl_->stats; }

}  // namespace frameless
