// Queries of the hybrid grid (grid_accel.h): 3-D DDA over the cells, a small ordered BVH walk in
// crowded cells, and the cone walk for soft shadows. The build is in grid_build.cpp.
//
// Multi-cell primitives: a hit is accepted wherever it is found (it is a real hit in [tmin, tmax])
// and the walk stops once the closest hit so far lies before the next cell. So rounding in the
// cell distances can only cost an extra cell, never lose or misplace a hit, unlike the classic
// "hit must lie in the current cell" rule. A small per-ray mailbox skips primitives tested in an
// earlier cell: a retest could only find the same hit again.
#include "core/accel/grid_accel.h"

#include <cfloat>
#include <type_traits>

#include "core/accel/robust_far.h"
#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"

namespace frameless {
namespace {

constexpr uint32_t kMailbox = 32;  // direct-mapped, per ray: catches primitives in adjacent cells
constexpr int kCellStackSize = 80;  // cell BVHs: SAH to depth 32, then medians (<= 32 more)

// The one place a primitive id becomes an intersection test (closest hit, or any hit when
// kAnyHit): triangles, spheres, then spline patches (ids from first_patch(), each walking its own
// BVH). A new primitive kind adds a branch here and its bounds in primitive_bounds
// (grid_build.cpp).
template <bool kAnyHit>
inline bool intersect_primitive(const Geometry& g, uint32_t id, const Ray& ray,
                                const TriangleRay& tr, float tmax, float& t, float& u, float& v) {
  const uint32_t nt = g.num_triangles(), fp = g.first_patch();
  if (id < nt) {
    const UVec3 tri = g.triangles[id];
    const Vec3* p = g.positions.data();
    return intersect_triangle(tr, p[tri.x], p[tri.y], p[tri.z], ray.tmin, tmax, t, u, v);
  }
  if (id < fp) {
    u = v = 0.0f;
    return intersect_sphere(ray.org, ray.dir, g.spheres[id - nt], ray.tmin, tmax, t);
  }
  const PatchSurface& patch = g.patches[id - fp];
  if constexpr (kAnyHit) return patch.occluded(ray, ray.tmin, tmax);
  return patch.intersect(ray, ray.tmin, tmax, t, u, v);
}

// Per-ray constants of the slab test (1 / dir is infinite for zero components).
struct CellRay {
  Vec3 org, inv, inv_far;
  bool neg[3];
};

inline CellRay make_cell_ray(const Ray& ray) {
  CellRay b;
  b.org = ray.org;
  for (int a = 0; a < 3; ++a) {
    b.inv[a] = 1.0f / ray.dir[a];
    b.inv_far[a] = b.inv[a] * kRobustFar;
    b.neg[a] = std::signbit(ray.dir[a]);
  }
  return b;
}

// Entry distance into [lo, hi] within [tmin, tmax], or false. A slab whose boundary holds the
// origin of a parallel ray gives NaN, which the comparisons ignore (the boundary counts inside).
inline bool slab_test(const Vec3& lo, const Vec3& hi, const CellRay& r, float tmin, float tmax,
                      float& t_enter) {
  float tn = tmin, tf = tmax;
  for (int a = 0; a < 3; ++a) {
    const float t0 = ((r.neg[a] ? hi[a] : lo[a]) - r.org[a]) * r.inv[a];
    const float t1 = ((r.neg[a] ? lo[a] : hi[a]) - r.org[a]) * r.inv_far[a];
    tn = t0 > tn ? t0 : tn;
    tf = t1 < tf ? t1 : tf;
  }
  t_enter = tn;
  return tn <= tf;
}

// State of one closest-hit (or any-hit) walk.
template <bool kAnyHit>
struct Walk {
  const Geometry& g;
  const Ray& ray;
  const CellRay br;
  const TriangleRay tr;
  float tmax;
  Hit& hit;
  bool found = false;
  uint64_t nodes = 0, prims = 0;
  uint32_t mailbox[kMailbox];

  Walk(const Geometry& geom, const Ray& r, Hit& h)
      : g(geom),
        ray(r),
        br(make_cell_ray(r)),
        // Sphere-only scenes skip the shear set-up and its divisions.
        tr(geom.num_triangles() ? make_triangle_ray(r) : TriangleRay{}),
        tmax(r.tmax),
        hit(h) {
    for (uint32_t& m : mailbox) m = kInvalidId;
  }

  // Tests one primitive; true when an any-hit walk may stop.
  bool test(uint32_t id) {
    uint32_t& m = mailbox[id & (kMailbox - 1)];
    if (m == id) return false;
    m = id;
    ++prims;
    float t, u, v;
    if (!intersect_primitive<kAnyHit>(g, id, ray, tr, tmax, t, u, v)) return false;
    found = true;
    if constexpr (kAnyHit) return true;
    tmax = t;
    hit.t = t, hit.u = u, hit.v = v, hit.prim = id;
    return false;
  }

  // Ordered walk of one cell's BVH; true when an any-hit walk may stop.
  bool cell_bvh(const GridAccel::Node* node_array, const uint32_t* ids, uint32_t root) {
    struct Entry {
      uint32_t node;
      float t;
    } stack[kCellStackSize];
    int sp = 0;
    float t_root;
    if (!slab_test(node_array[root].lo, node_array[root].hi, br, ray.tmin, tmax * kRobustFar,
                   t_root))
      return false;
    uint32_t i = root;
    for (;;) {
      ++nodes;
      const GridAccel::Node& n = node_array[i];
      if (n.count > 0) {
        for (uint32_t k = 0; k < n.count; ++k)
          if (test(ids[n.index + k])) return true;
      } else {
        const uint32_t l = i + 1, r = n.index;
        const float tmax_box = tmax * kRobustFar;
        float tl, tr_;
        const bool hl = slab_test(node_array[l].lo, node_array[l].hi, br, ray.tmin, tmax_box, tl);
        const bool hr = slab_test(node_array[r].lo, node_array[r].hi, br, ray.tmin, tmax_box, tr_);
        if (hl && hr) {
          // Nearer child first; the other waits with its entry distance.
          const bool left_first = tl <= tr_;
          stack[sp++] = left_first ? Entry{r, tr_} : Entry{l, tl};
          i = left_first ? l : r;
          continue;
        }
        if (hl | hr) {
          i = hl ? l : r;
          continue;
        }
      }
      // Pop the nearest pending child that may still hold a closer hit.
      for (;;) {
        if (sp == 0) return false;
        const Entry& e = stack[--sp];
        if (e.t <= tmax * kRobustFar) {
          i = e.node;
          break;
        }
      }
    }
  }
};

}  // namespace

template <bool kAnyHit>
bool GridAccel::traverse(const Ray& ray, Hit& hit, TraversalCounts* counts) const {
  if (offsets_.empty()) return false;
  if (!is_finite(ray.org) || !is_finite(ray.dir) || !(ray.tmin <= ray.tmax)) return false;
  Walk<kAnyHit> w(*geom_, ray, hit);
  // Clip the ray to the grid box.
  float t0 = ray.tmin, t1 = ray.tmax * kRobustFar;
  if (!slab_test(lo_, hi_, w.br, t0, t1, t0)) return false;

  // DDA set-up. An axis along which the ray crosses no cell boundary at any finite distance (zero
  // or denormal direction component) never steps.
  int idx[3], step[3];
  float next[3], cell_t[3], base_t[3];
  int32_t stride[3] = {1, res_[0], res_[0] * res_[1]};
  uint32_t c = 0;
  for (int a = 0; a < 3; ++a) {
    const float p = ray.org[a] + t0 * ray.dir[a];
    // max(0, NaN) is 0: the conversion below never sees NaN or infinity.
    const float f = std::min(std::max(0.0f, (p - lo_[a]) * inv_cell_[a]), float(res_[a] - 1));
    idx[a] = int(f);
    c += uint32_t(idx[a] * stride[a]);
    base_t[a] = (lo_[a] - ray.org[a]) * w.br.inv[a];
    cell_t[a] = cell_[a] * w.br.inv[a];
    if (std::abs(base_t[a]) <= FLT_MAX && std::abs(cell_t[a]) <= FLT_MAX) {
      step[a] = ray.dir[a] > 0.0f ? 1 : -1;
      // Boundary k of axis a lies at lo + k * cell: distance recomputed, not accumulated.
      next[a] = fmadd(float(idx[a] + (step[a] > 0)), cell_t[a], base_t[a]);
    } else {
      step[a] = 0;
      next[a] = kInfinity;
    }
    stride[a] *= step[a];
  }

  const uint32_t* off = offsets_.data();
  const uint32_t* ids = ids_.data();
  const uint64_t* occupied = occupied_.data();
  const Node* nodes = nodes_.data();
  // The axis loop is unrolled so that indices and distances stay in registers.
  auto advance = [&](auto axis, float& n) {
    constexpr int a = decltype(axis)::value;
    if (!(n <= std::min(t1, w.tmax * kRobustFar)) || step[a] == 0) return false;
    idx[a] += step[a];
    if (uint32_t(idx[a]) >= uint32_t(res_[a])) return false;
    c += uint32_t(stride[a]);
    n = fmadd(float(idx[a] + (step[a] > 0)), cell_t[a], base_t[a]);
    return true;
  };
  float nx = next[0], ny = next[1], nz = next[2];
  for (;;) {
    ++w.nodes;
    // The bitmap (L1-resident for most grids) skips empty cells without touching the offsets.
    if (occupied[c >> 6] >> (c & 63) & 1) {
      const uint32_t b = off[c], e = off[c + 1];
      if (e - b > list_max_) {
        if (w.cell_bvh(nodes, ids, ids[b])) break;
      } else {
        bool stop = false;
        for (uint32_t k = b; k < e && !stop; ++k) stop = w.test(ids[k]);
        if (stop) break;
      }
    }
    // The next cell starts at the nearest boundary; stop when the closest hit lies before it.
    const bool go = nx < ny ? (nx < nz ? advance(std::integral_constant<int, 0>{}, nx)
                                       : advance(std::integral_constant<int, 2>{}, nz))
                            : (ny < nz ? advance(std::integral_constant<int, 1>{}, ny)
                                       : advance(std::integral_constant<int, 2>{}, nz));
    if (!go) break;
  }
  if (counts) counts->nodes += w.nodes, counts->prims += w.prims;
  return w.found;
}

bool GridAccel::intersect(const Ray& ray, Hit& hit, TraversalCounts* counts) const {
  return traverse<false>(ray, hit, counts);
}

bool GridAccel::occluded(const Ray& ray, TraversalCounts* counts) const {
  Hit unused;
  return traverse<true>(ray, unused, counts);
}

namespace {

// Accel's cone test (accel.cpp, cone_children) on one box: the box grown by the cone's radius at
// its far end along the axis must be entered by the axis ray within [0, tmax].
inline bool cone_meets_box(const Vec3& lo, const Vec3& hi, const Ray& ray, const CellRay& r,
                           float tan_half, float tmax) {
  float far_t = 0.0f;  // largest depth along the axis of any box corner
  for (int a = 0; a < 3; ++a)
    far_t += std::max((lo[a] - ray.org[a]) * ray.dir[a], (hi[a] - ray.org[a]) * ray.dir[a]);
  if (!(far_t >= 0.0f)) return false;  // wholly behind the apex
  const float grow = tan_half * std::min(far_t, tmax) * 1.0001f + 1e-30f;
  float t_enter;
  return slab_test(lo - Vec3(grow), hi + Vec3(grow), r, 0.0f, tmax, t_enter);
}

}  // namespace

bool GridAccel::visit_cone(const Ray& ray, float tan_half, Accel::ConeVisitor& visitor) const {
  if (offsets_.empty() || !is_finite(ray.org) || !is_finite(ray.dir)) return true;
  const Vec3 &o = ray.org, &d = ray.dir;
  const float th = tan_half > 0.0f ? tan_half : 0.0f;
  const CellRay br = make_cell_ray(ray);
  const float tmax = ray.tmax * kRobustFar;
  // Nothing in the grid lies deeper along the axis than its deepest corner.
  float deepest = 0.0f;
  for (int a = 0; a < 3; ++a) deepest += std::max((lo_[a] - o[a]) * d[a], (hi_[a] - o[a]) * d[a]);
  const float t_end = std::min(tmax, deepest * 1.0001f);
  const int m = std::abs(d.x) >= std::abs(d.y) ? (std::abs(d.x) >= std::abs(d.z) ? 0 : 2)
                                               : (std::abs(d.y) >= std::abs(d.z) ? 1 : 2);
  if (!(t_end >= 0.0f) || d[m] == 0.0f) return true;
  const int a1 = m == 2 ? 0 : m + 1, a2 = a1 == 2 ? 0 : a1 + 1;
  auto cell_of = [this](int a, float x) {
    return int(std::min(std::max(0.0f, (x - lo_[a]) * inv_cell_[a]), float(res_[a] - 1)));
  };
  uint32_t mailbox[64];  // fewer repeats of primitives that span cells, for free
  for (uint32_t& e : mailbox) e = kInvalidId;
  auto visit = [&](uint32_t id) {
    uint32_t& e = mailbox[id & 63];
    if (e == id) return true;
    e = id;
    return visitor.leaf(id, 1);
  };

  // Walk the cells slab by slab along the dominant axis m. A point of the cone is within the
  // cone's radius r of the axis point at its depth s, so it lies in slab k only if o[m] + s d[m]
  // is within r of the slab, and then in the other axes within r(s) of the axis over those s.
  const float r_max = th * t_end * 1.0001f + pad_;  // pad_ covers the rounding below
  const float z_a = o[m], z_b = o[m] + t_end * d[m];
  const int k0 = cell_of(m, std::min(z_a, z_b) - r_max);
  const int k1 = cell_of(m, std::max(z_a, z_b) + r_max);
  for (int k = k0; k <= k1; ++k) {
    float ta = (lo_[m] + float(k) * cell_[m] - r_max - o[m]) / d[m];
    float tb = (lo_[m] + float(k + 1) * cell_[m] + r_max - o[m]) / d[m];
    if (ta > tb) std::swap(ta, tb);
    ta = std::max(ta, 0.0f), tb = std::min(tb, t_end);
    if (!(ta <= tb)) continue;
    const float r = th * tb * 1.0001f + pad_;
    int i0[3], i1[3];
    i0[m] = i1[m] = k;
    for (int a : {a1, a2}) {
      const float pa = o[a] + ta * d[a], pb = o[a] + tb * d[a];
      i0[a] = cell_of(a, std::min(pa, pb) - r);
      i1[a] = cell_of(a, std::max(pa, pb) + r);
    }
    for (int z = i0[2]; z <= i1[2]; ++z)
      for (int y = i0[1]; y <= i1[1]; ++y)
        for (int x = i0[0]; x <= i1[0]; ++x) {
          const size_t c = (size_t(z) * res_[1] + y) * res_[0] + x;
          if (!(occupied_[c >> 6] >> (c & 63) & 1)) continue;
          const Vec3 xyz{float(x), float(y), float(z)};
          if (!cone_meets_box(lo_ + xyz * cell_ - Vec3(pad_),
                              lo_ + (xyz + 1.0f) * cell_ + Vec3(pad_), ray, br, th, tmax))
            continue;
          const uint32_t b = offsets_[c], e = offsets_[c + 1];
          if (e - b <= list_max_) {
            for (uint32_t i = b; i < e; ++i)
              if (!visit(ids_[i])) return false;
            continue;
          }
          // Crowded cell: prune its BVH with the same test.
          uint32_t stack[kCellStackSize];
          int sp = 0;
          stack[sp++] = ids_[b];
          while (sp > 0) {
            const Node& n = nodes_[stack[--sp]];
            if (!cone_meets_box(n.lo, n.hi, ray, br, th, tmax)) continue;
            if (n.count == 0) {
              stack[sp++] = n.index;
              stack[sp++] = uint32_t(&n - nodes_.data()) + 1;
              continue;
            }
            for (uint32_t i = 0; i < n.count; ++i)
              if (!visit(ids_[n.index + i])) return false;
          }
        }
  }
  return true;
}

}  // namespace frameless
