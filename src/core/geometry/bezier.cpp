// Bicubic Bézier patches: evaluation, limit normals, subdivision, and the per-patch BVH traversed
// near-to-far with Broyden's method in the leaves (Parker et al. 1999, sec. 3.3).
#include "core/geometry/bezier.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace frameless {
namespace {

using DVec3 = glm::dvec3;

// Cubic Bernstein basis at t with its first and second derivatives. The basis has a fixed size,
// so every query keeps it in registers or on its own stack: unlike the seed's general NURBS basis
// functions, nothing needs a per-thread scratch area (and so no lock and no thread index).
struct Basis {
  double b[4], d1[4], d2[4];
};

Basis basis(double t) {
  const double s = 1.0 - t;
  return {{s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t},
          {-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t},
          {6.0 * s, 18.0 * t - 12.0, 6.0 - 18.0 * t, 6.0 * t}};
}

DVec3 point(const BezierPatch& patch, int k) { return DVec3(patch.p[k]); }

// Position and first partials; the hot path of the solver.
DVec3 eval(const BezierPatch& patch, double u, double v, DVec3& pu, DVec3& pv) {
  const Basis bu = basis(u), bv = basis(v);
  DVec3 p(0.0);
  pu = pv = DVec3(0.0);
  for (int i = 0; i < 4; ++i) {
    // Contract each row along u first: 4 points per row instead of 16 per output.
    DVec3 row(0.0), row_du(0.0);
    for (int j = 0; j < 4; ++j) {
      row += bu.b[j] * point(patch, 4 * i + j);
      row_du += bu.d1[j] * point(patch, 4 * i + j);
    }
    p += bv.b[i] * row;
    pu += bv.b[i] * row_du;
    pv += bv.d1[i] * row;
  }
  return p;
}

struct Second {
  DVec3 puu{0.0}, puv{0.0}, pvv{0.0};
};

Second second(const BezierPatch& patch, double u, double v) {
  const Basis bu = basis(u), bv = basis(v);
  Second s;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const DVec3 q = point(patch, 4 * i + j);
      s.puu += bv.b[i] * bu.d2[j] * q;
      s.puv += bv.d1[i] * bu.d1[j] * q;
      s.pvv += bv.d2[i] * bu.b[j] * q;
    }
  return s;
}

// Largest extent of the control points: the patch's coordinate scale.
double patch_scale(const BezierPatch& patch) {
  Vec3 lo(patch.p[0]), hi(patch.p[0]);
  for (const Vec3& q : patch.p) lo = glm::min(lo, q), hi = glm::max(hi, q);
  return double(max_component(hi - lo));
}

// A cross product counts as a normal when it is not tiny against the patch's scale nor against
// `mag`, the size of the products it came from (parallel tangents).
bool usable(const DVec3& n, double mag, double scale) {
  const double len = glm::length(n);
  return std::isfinite(len) && len > 1e-9 * scale * scale && len > 1e-7 * mag;
}

// Blossom f(t1, t2, t3) of a cubic: de Casteljau with a different parameter at each level.
DVec3 blossom(const DVec3 c[4], double t1, double t2, double t3) {
  const DVec3 a0 = glm::mix(c[0], c[1], t1), a1 = glm::mix(c[1], c[2], t1), a2 = glm::mix(c[2], c[3], t1);
  const DVec3 b0 = glm::mix(a0, a1, t2), b1 = glm::mix(a1, a2, t2);
  return glm::mix(b0, b1, t3);
}

// Control points of the cubic restricted to [a, b]: the blossoms f(a,a,a), f(a,a,b), f(a,b,b), f(b,b,b).
void subcurve(const DVec3 c[4], double a, double b, DVec3 out[4]) {
  out[0] = blossom(c, a, a, a);
  out[1] = blossom(c, a, a, b);
  out[2] = blossom(c, a, b, b);
  out[3] = blossom(c, b, b, b);
}

void subpatch(const BezierPatch& patch, double u0, double u1, double v0, double v1, DVec3 out[16]) {
  DVec3 rows[16];
  for (int i = 0; i < 4; ++i) {
    const DVec3 c[4] = {point(patch, 4 * i), point(patch, 4 * i + 1), point(patch, 4 * i + 2),
                        point(patch, 4 * i + 3)};
    subcurve(c, u0, u1, rows + 4 * i);
  }
  for (int j = 0; j < 4; ++j) {
    const DVec3 c[4] = {rows[j], rows[4 + j], rows[8 + j], rows[12 + j]};
    DVec3 col[4];
    subcurve(c, v0, v1, col);
    for (int i = 0; i < 4; ++i) out[4 * i + j] = col[i];
  }
}

// Every second bit of a Morton index: the column (even bits) or the row (odd bits, after >> 1).
uint32_t compact_bits(uint32_t x) {
  x &= 0x55555555u;
  x = (x | (x >> 1)) & 0x33333333u;
  x = (x | (x >> 2)) & 0x0f0f0f0fu;
  x = (x | (x >> 4)) & 0x00ff00ffu;
  x = (x | (x >> 8)) & 0x0000ffffu;
  return x;
}

constexpr size_t level_offset(int level) { return ((size_t(1) << (2 * level)) - 1) / 3; }

// Leaf column/row c of n, widened by `overlap` leaf widths on each side and clamped to the patch.
void leaf_interval(uint32_t c, int n, double overlap, double& lo, double& hi) {
  const double w = 1.0 / n;
  lo = std::max(0.0, (c - overlap) * w);
  hi = std::min(1.0, (c + 1 + overlap) * w);
}

constexpr int kMaxIterations = 8;
// Broyden converges when every residual component is within kTolerance times the patch's scale:
// ~10x the single precision of the control points, far below the 1e-4 depth accuracy asked for.
constexpr double kTolerance = 1e-6;
// Boxes grow by a little more than that, so that a root within tolerance is inside its box.
constexpr double kPad = 1e-5;
// Roots this far outside the patch's [0,1] still count (and are clamped): the seams between
// patches lie on the domain's edge, where a root's last bits decide which side it falls on;
// without this slack both neighbours could reject a ray through their shared edge.
constexpr double kEdgeSlack = 1e-5;

struct Root {
  double t, u, v;
  double cosine;  // |cos| of the angle between the ray and the normal there
  int iterations;
};

// Solves F(u,v,t) = P(u,v) - (o + t d) = 0 by Broyden's method in its 3-D form (t is an unknown,
// so no per-ray pair of planes is needed). Starts at the middle of the parameter interval
// [u0,u1] x [v0,v1], t from projecting P there on the ray, with the exact Jacobian [Pu Pv -d]
// there; rank-1 ("good" Broyden) updates after that instead of new partials. Converged when every
// residual component is within tol; false when it does not converge in kMaxIterations, leaves
// the neighbourhood of the interval, or the Jacobian turns singular (ray tangent to the surface).
bool broyden(const BezierPatch& patch, const DVec3& o, const DVec3& d, double u0, double u1,
             double v0, double v1, double tol, Root& root) {
  // Iterates that wander more than the interval's width away head for another leaf's root; that
  // leaf finds it from its own start.
  const double wu = u1 - u0, wv = v1 - v0;
  double u = 0.5 * (u0 + u1), v = 0.5 * (v0 + v1);
  DVec3 pu, pv;
  DVec3 p = eval(patch, u, v, pu, pv);
  double t = glm::dot(p - o, d) / glm::dot(d, d);
  DVec3 f = p - (o + t * d);
  DVec3 c0 = pu, c1 = pv, c2 = -d;  // Jacobian columns
  for (int k = 1; k <= kMaxIterations; ++k) {
    // Cramer's rule for J dx = -f.
    const DVec3 c12 = glm::cross(c1, c2);
    const double det = glm::dot(c0, c12);
    if (!(std::abs(det) > 1e-12 * glm::length(c0) * glm::length(c1) * glm::length(c2))) return false;
    const DVec3 dx = DVec3(-glm::dot(f, c12), -glm::dot(c0, glm::cross(f, c2)),
                           -glm::dot(c0, glm::cross(c1, f))) / det;
    u += dx.x, v += dx.y, t += dx.z;
    if (!(u > u0 - wu && u < u1 + wu && v > v0 - wv && v < v1 + wv) || !std::isfinite(t)) return false;
    p = eval(patch, u, v, pu, pv);
    const DVec3 fn = p - (o + t * d);
    const DVec3 r = glm::abs(fn);
    if (std::max(r.x, std::max(r.y, r.z)) <= tol) {
      const DVec3 n = glm::cross(pu, pv);
      const double cosine = std::abs(glm::dot(n, d)) / (glm::length(n) * glm::length(d));
      root = {t, u, v, std::isfinite(cosine) ? cosine : 1.0, k};
      return true;
    }
    // J += (df - J dx) dx^T / (dx . dx): the secant condition along the last step.
    const DVec3 jdx = c0 * dx.x + c1 * dx.y + c2 * dx.z;
    const DVec3 g = (fn - f - jdx) / glm::dot(dx, dx);
    c0 += g * dx.x, c1 += g * dx.y, c2 += g * dx.z;
    f = fn;
  }
  return false;
}

// Slab test against [tmin, tmax]; the exit distance is pushed out by 2 gamma(3) (pbrt) so that
// rounding never loses a box the ray grazes. A NaN slab (origin on a slab plane of a zero
// direction component) is dropped, which keeps the box.
bool slab(const Vec3& lo, const Vec3& hi, const Vec3& org, const Vec3& inv, float tmin, float tmax,
          float& tnear) {
  float t0 = tmin, t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    const float tl = (lo[a] - org[a]) * inv[a], th = (hi[a] - org[a]) * inv[a];
    t0 = std::max(t0, std::min(tl, th));
    t1 = std::min(t1, std::max(tl, th) * 1.0000003f);
  }
  tnear = t0;
  return t0 <= t1;
}

struct Domain {
  double u0, u1, v0, v1;
};

// Box of the control points of the patch over d, grown by pad: contains that part of the surface.
void domain_box(const BezierPatch& patch, const Domain& d, float pad, Vec3& lo, Vec3& hi) {
  DVec3 q[16];
  subpatch(patch, d.u0, d.u1, d.v0, d.v1, q);
  DVec3 a = q[0], b = q[0];
  for (const DVec3& x : q) a = glm::min(a, x), b = glm::max(b, x);
  lo = Vec3(a) - pad, hi = Vec3(b) + pad;
}

constexpr int kRefineLevels = 2;
constexpr double kGrazing = 0.2;  // below this |cos| a leaf may hold two close crossings

// The search for one ray's root in one leaf; everything on the stack.
struct LeafSearch {
  const BezierPatch& patch;
  Vec3 org, inv;    // slab tests of the boxes made on the fly
  DVec3 o, d;       // the solver
  float tmin;
  Domain accept;    // the leaf's overlapped domain (with the slack on the patch's edge)
  double overlap, pad, tol;
  PatchHitStats* stats;

  // A root in `accept` with t in [tmin, tmax], Broyden starting in the middle of dom. That start
  // can miss the root it should find, mostly on grazing rays, nearly in the tangent plane there:
  // the first step shoots off, or to the other of two close crossings. So when it fails, or
  // converges outside `accept` or [tmin, tmax], or converges to a grazing crossing (which may
  // have a nearer twin), dom is split on the fly, down to kRefineLevels below the leaf.
  // kRefineLevels = 0 is the seed's plain method.
  bool solve(const Domain& dom, float tmax, int refine, Root& root) const {
    if (stats) ++stats->solves;
    if (broyden(patch, o, d, dom.u0, dom.u1, dom.v0, dom.v1, tol, root)) {
      if (stats) ++stats->converged, stats->iterations += uint64_t(root.iterations);
      const float t = float(root.t);
      if (root.u >= accept.u0 && root.u <= accept.u1 && root.v >= accept.v0 && root.v <= accept.v1 &&
          t >= tmin && t <= tmax) {
        Root nearer;
        const float before = t * (1.0f - 1e-5f);  // a distinct crossing, not this one again
        if (refine > 0 && root.cosine < kGrazing && before >= tmin && quadrants(dom, before, refine - 1, nearer))
          root = nearer;
        return true;
      }
    }
    return refine > 0 && quadrants(dom, tmax, refine - 1, root);
  }

  // The quadrants of dom (overlapping like the leaves, within `accept`) whose boxes, from their
  // own control points, the ray enters before tmax; solved near-to-far.
  bool quadrants(const Domain& dom, float tmax, int refine, Root& root) const {
    struct Child {
      Domain dom;
      float tnear;
    } hit[4];
    int k = 0;
    const double hu = 0.5 * (dom.u1 - dom.u0), hv = 0.5 * (dom.v1 - dom.v0);
    for (int c = 0; c < 4; ++c) {
      const double u0 = dom.u0 + (c & 1) * hu, v0 = dom.v0 + (c >> 1) * hv;
      const Domain cd = {std::max(accept.u0, u0 - overlap * hu), std::min(accept.u1, u0 + (1 + overlap) * hu),
                         std::max(accept.v0, v0 - overlap * hv), std::min(accept.v1, v0 + (1 + overlap) * hv)};
      Vec3 lo, hi;
      domain_box(patch, cd, float(pad), lo, hi);
      float tnear;
      if (!slab(lo, hi, org, inv, tmin, tmax, tnear)) continue;
      hit[k] = {cd, tnear};
      for (int j = k++; j > 0 && hit[j - 1].tnear > hit[j].tnear; --j) std::swap(hit[j - 1], hit[j]);
    }
    for (int j = 0; j < k; ++j)
      if (solve(hit[j].dom, tmax, refine, root)) return true;
    return false;
  }
};

}  // namespace

Vec3 bezier_eval(const BezierPatch& patch, float u, float v, Vec3* du, Vec3* dv) {
  DVec3 pu, pv;
  const DVec3 p = eval(patch, u, v, pu, pv);
  if (du) *du = Vec3(pu);
  if (dv) *dv = Vec3(pv);
  return Vec3(p);
}

Vec3 bezier_normal(const BezierPatch& patch, float u, float v) {
  const double scale = patch_scale(patch);
  DVec3 pu, pv;
  eval(patch, u, v, pu, pv);
  DVec3 n = glm::cross(pu, pv);
  if (!usable(n, glm::length(pu) * glm::length(pv), scale)) {
    // Degenerate here: approach (u,v) from inside, along (u,v) + h (a,b) towards the centre. As
    // du x dv vanishes at h = 0, to first order the normal is h times the derivative of du x dv
    // along (a,b), so that derivative's direction is the limit normal (at the teapot's poles,
    // Puv x Pv: the axis).
    DVec3 dir(0.5 - double(u), 0.5 - double(v), 0.0);
    dir = glm::length(dir) > 0.0 ? dir / glm::length(dir) : DVec3(1.0, 0.0, 0.0);
    const Second s = second(patch, u, v);
    const DVec3 dpu = s.puu * dir.x + s.puv * dir.y, dpv = s.puv * dir.x + s.pvv * dir.y;
    n = glm::cross(dpu, pv) + glm::cross(pu, dpv);
    const double mag = glm::length(dpu) * glm::length(pv) + glm::length(pu) * glm::length(dpv);
    // Still nothing (a corner where more collapses): step inside until the cross product shows.
    if (!usable(n, mag, scale))
      for (double h = 1e-4; h <= 1.0; h *= 4.0) {
        eval(patch, u + h * dir.x, v + h * dir.y, pu, pv);
        n = glm::cross(pu, pv);
        if (usable(n, glm::length(pu) * glm::length(pv), scale)) break;
      }
  }
  const double len = glm::length(n);
  if (!(len > 0.0) || !std::isfinite(len)) return Vec3(0.0f, 0.0f, 1.0f);  // no surface at all
  return Vec3(n / len);
}

BezierPatch bezier_subpatch(const BezierPatch& patch, float u0, float u1, float v0, float v1) {
  DVec3 q[16];
  subpatch(patch, u0, u1, v0, v1, q);
  BezierPatch out;
  for (int k = 0; k < 16; ++k) out.p[k] = Vec3(q[k]);
  return out;
}

PatchSurface::PatchSurface(const BezierPatch& patch, int depth, float overlap)
    : patch_(patch), depth_(std::clamp(depth, 0, kMaxPatchDepth)),
      overlap_(overlap > 0.0f ? std::min(overlap, 0.5f) : 0.0f), scale_(float(patch_scale(patch))) {
  const int n = 1 << depth_;
  boxes_.resize(level_offset(depth_ + 1));
  // Leaves: the box of the sub-control points of each overlapped leaf domain.
  Box* leaves = boxes_.data() + level_offset(depth_);
  for (uint32_t m = 0; m < uint32_t(n) * uint32_t(n); ++m) {
    Domain d;
    leaf_interval(compact_bits(m), n, overlap_, d.u0, d.u1);
    leaf_interval(compact_bits(m >> 1), n, overlap_, d.v0, d.v1);
    domain_box(patch, d, kPad * scale_, leaves[m].lo, leaves[m].hi);
  }
  // Bottom-up: a parent is the union of its 4 children, tighter than a box of its own control
  // points since the subdivided control meshes converge to the surface.
  for (int level = depth_ - 1; level >= 0; --level) {
    Box* parents = boxes_.data() + level_offset(level);
    const Box* children = boxes_.data() + level_offset(level + 1);
    for (size_t m = 0; m < (size_t(1) << (2 * level)); ++m) {
      Box b = children[4 * m];
      for (int c = 1; c < 4; ++c)
        b = {glm::min(b.lo, children[4 * m + c].lo), glm::max(b.hi, children[4 * m + c].hi)};
      parents[m] = b;
    }
  }
}

Vec3 PatchSurface::lo() const { return boxes_.empty() ? Vec3(0.0f) : boxes_[0].lo; }
Vec3 PatchSurface::hi() const { return boxes_.empty() ? Vec3(0.0f) : boxes_[0].hi; }

size_t PatchSurface::bytes() const { return sizeof(*this) + boxes_.capacity() * sizeof(Box); }

// Roots carry a relative error of about kTolerance of the patch: a ray leaving the surface must
// not find its own start again, so roots closer than ten times that are not hits (every caller,
// BVH, grid and soft shadows, gets the same rule).
float PatchSurface::self_hit_distance() const { return float(10.0 * kTolerance) * scale_; }

bool PatchSurface::intersect(const Ray& ray, float tmin, float tmax, float& t, float& u, float& v,
                             PatchHitStats* stats) const {
  return traverse<false>(ray, std::max(tmin, self_hit_distance()), tmax, t, u, v, stats);
}

bool PatchSurface::occluded(const Ray& ray, float tmin, float tmax) const {
  float t, u, v;
  return traverse<true>(ray, std::max(tmin, self_hit_distance()), tmax, t, u, v, nullptr);
}

template <bool kAny>
bool PatchSurface::traverse(const Ray& ray, float tmin, float tmax, float& t_out, float& u_out,
                            float& v_out, PatchHitStats* stats) const {
  if (boxes_.empty() || !(tmin <= tmax)) return false;
  const Vec3 inv = 1.0f / ray.dir;
  const int n = 1 << depth_;
  // Each inner node pops one entry and pushes at most four: 3 per level plus the root.
  struct Entry {
    uint32_t m;
    int level;
    float tnear;
  };
  Entry stack[3 * kMaxPatchDepth + 2];
  int sp = 0;
  float tnear;
  if (!slab(boxes_[0].lo, boxes_[0].hi, ray.org, inv, tmin, tmax, tnear)) return false;
  stack[sp++] = {0, 0, tnear};
  if (depth_ == 0 && stats) ++stats->leaf_tests;
  float best = tmax;
  bool found = false;
  while (sp > 0) {
    const Entry e = stack[--sp];
    if (e.tnear > best) continue;  // a closer hit was found after this was pushed
    if (e.level == depth_) {
      // Only roots of this leaf's (overlapped) domain count, plus the slack on the patch's edge.
      Domain leaf;
      leaf_interval(compact_bits(e.m), n, overlap_, leaf.u0, leaf.u1);
      leaf_interval(compact_bits(e.m >> 1), n, overlap_, leaf.v0, leaf.v1);
      const LeafSearch search = {
          patch_, ray.org, inv, DVec3(ray.org), DVec3(ray.dir), tmin,
          {leaf.u0 > 0.0 ? leaf.u0 : -kEdgeSlack, leaf.u1 < 1.0 ? leaf.u1 : 1.0 + kEdgeSlack,
           leaf.v0 > 0.0 ? leaf.v0 : -kEdgeSlack, leaf.v1 < 1.0 ? leaf.v1 : 1.0 + kEdgeSlack},
          overlap_, kPad * scale_, kTolerance * scale_, stats};
      Root r;
      if (!search.solve(leaf, best, kRefineLevels, r)) continue;
      best = float(r.t);
      u_out = float(std::clamp(r.u, 0.0, 1.0));
      v_out = float(std::clamp(r.v, 0.0, 1.0));
      found = true;
      if constexpr (kAny) break;
      continue;
    }
    // Children near-to-far: sort the hit ones by entry distance, push the farthest first.
    const Box* children = boxes_.data() + level_offset(e.level + 1);
    Entry hit[4];
    int k = 0;
    for (uint32_t c = 0; c < 4; ++c) {
      const uint32_t m = 4 * e.m + c;
      if (!slab(children[m].lo, children[m].hi, ray.org, inv, tmin, best, tnear)) continue;
      hit[k] = {m, e.level + 1, tnear};
      for (int j = k++; j > 0 && hit[j - 1].tnear < hit[j].tnear; --j) std::swap(hit[j - 1], hit[j]);
      if (stats && e.level + 1 == depth_) ++stats->leaf_tests;
    }
    for (int j = 0; j < k; ++j) stack[sp++] = hit[j];
  }
  if (found) t_out = best;
  return found;
}

}  // namespace frameless
