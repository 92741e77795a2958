// Cell walk, macrocell skipping and the per-cell cubic of the trilinear interpolant.
#include "core/volume/isosurface.h"

#include <algorithm>
#include <cmath>

#include "core/volume/trilinear.h"

namespace frameless {
namespace {

// f(s) = A s^3 + B s^2 + C s + D: the interpolant minus iso along u = a + s b (local coordinates).
struct Cubic {
  double A = 0, B = 0, C = 0, D = 0;
  double operator()(double s) const { return ((A * s + B) * s + C) * s + D; }
};

Cubic cubic_along(const double (&k)[8], const double a[3], const double b[3], double iso) {
  Cubic f;
  for (int corner = 0; corner < 8; ++corner) {
    // Each axis contributes (1 - u) or u: p + q s.
    double p[3], q[3];
    for (int ax = 0; ax < 3; ++ax) {
      const bool hi = (corner >> ax) & 1;
      p[ax] = hi ? a[ax] : 1.0 - a[ax];
      q[ax] = hi ? b[ax] : -b[ax];
    }
    const double w = k[corner];
    f.D += w * p[0] * p[1] * p[2];
    f.C += w * (q[0] * p[1] * p[2] + p[0] * q[1] * p[2] + p[0] * p[1] * q[2]);
    f.B += w * (q[0] * q[1] * p[2] + q[0] * p[1] * q[2] + p[0] * q[1] * q[2]);
    f.A += w * q[0] * q[1] * q[2];
  }
  f.D -= iso;
  return f;
}

// The first root of f in [0, len], if any: f is monotone between its extrema, so the first
// interval whose ends differ in sign (or end on zero) holds it; bisection narrows it to the last
// bit.
bool first_root(const Cubic& f, double len, double& s) {
  double cuts[4] = {0.0, len, len, len};
  int n = 1;
  // Extrema: 3A s^2 + 2B s + C = 0.
  const double qa = 3.0 * f.A, qb = 2.0 * f.B, qc = f.C;
  double r[2];
  int nr = 0;
  if (std::abs(qa) > 1e-300) {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0) {
      const double sq = std::sqrt(disc);
      const double q = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));  // the stable pair of roots
      r[nr++] = q / qa;
      if (q != 0.0) r[nr++] = qc / q;
    }
  } else if (std::abs(qb) > 1e-300) {
    r[nr++] = -qc / qb;
  }
  if (nr == 2 && r[0] > r[1]) std::swap(r[0], r[1]);
  for (int i = 0; i < nr; ++i)
    if (r[i] > 0.0 && r[i] < len) cuts[n++] = r[i];
  cuts[n++] = len;
  double a = cuts[0], fa = f(a);
  if (fa == 0.0) {
    s = a;
    return true;
  }
  for (int i = 1; i < n; ++i) {
    double b = cuts[i];
    const double fb = f(b);
    if ((fa < 0.0) != (fb < 0.0) || fb == 0.0) {
      for (int it = 0; it < 60 && b - a > 1e-12 * (1.0 + len); ++it) {  // bisection
        const double m = 0.5 * (a + b), fm = f(m);
        if ((fm < 0.0) == (fa < 0.0) && fm != 0.0) {
          a = m;
          fa = fm;
        } else {
          b = m;
        }
      }
      s = b;
      return true;
    }
    a = b;
    fa = fb;
  }
  return false;
}

// The walk over one range of cells: cells [lo, hi] (inclusive, per axis), from parameter t to
// t_end. Returns 1 on a hit (t set), 0 when the walk left the range at t (updated), -1 at t_end.
template <class Voxels>
int walk_cells(const Voxels& v, double iso, const double o[3], const double d[3], const int lo[3],
               const int hi[3], double& t, double t_end, float& t_hit) {
  int c[3];
  double next[3];
  int step[3];
  for (int ax = 0; ax < 3; ++ax) {
    const double p = o[ax] + t * d[ax];
    int ci = int(std::floor(p));
    if (d[ax] < 0.0 && double(ci) == p) --ci;  // on a face, moving down: the cell below
    c[ax] = std::clamp(ci, lo[ax], hi[ax]);
    if (d[ax] > 0.0) {
      step[ax] = 1;
      next[ax] = (double(c[ax] + 1) - o[ax]) / d[ax];
    } else if (d[ax] < 0.0) {
      step[ax] = -1;
      next[ax] = (double(c[ax]) - o[ax]) / d[ax];
    } else {
      step[ax] = 0;
      next[ax] = kInfinity;
    }
  }
  while (true) {
    const int ax = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    const double t_out = std::min(next[ax], t_end);
    double k[8];
    v.corners(c[0], c[1], c[2], k);
    const double kmin = *std::min_element(k, k + 8), kmax = *std::max_element(k, k + 8);
    if (kmin <= iso && iso <= kmax && t_out >= t) {
      double a[3], b[3];
      for (int i = 0; i < 3; ++i) {
        a[i] = o[i] + t * d[i] - double(c[i]);
        b[i] = d[i];
      }
      double s;
      if (first_root(cubic_along(k, a, b, iso), t_out - t, s)) {
        t_hit = float(t + s);
        return 1;
      }
    }
    if (t_out >= t_end) return -1;
    t = std::max(t, t_out);
    c[ax] += step[ax];
    // From the face's own coordinate, not by adding up deltas: any walk, with or without the
    // macrocells, then gives a cell the same entry and exit, so both find the same roots.
    next[ax] = (double(c[ax] + (step[ax] > 0 ? 1 : 0)) - o[ax]) / d[ax];
    if (c[ax] < lo[ax] || c[ax] > hi[ax]) return 0;
  }
}

}  // namespace

bool clip_to_box(const Vec3& lo, const Vec3& hi, const Vec3& org, const Vec3& dir, float& t0,
                 float& t1) {
  for (int ax = 0; ax < 3; ++ax) {
    if (dir[ax] == 0.0f) {
      if (org[ax] < lo[ax] || org[ax] > hi[ax]) return false;
      continue;
    }
    const float inv = 1.0f / dir[ax];
    float a = (lo[ax] - org[ax]) * inv, b = (hi[ax] - org[ax]) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 <= t1;
}

bool intersect_isosurface(const VolumeGrid& g, const Macrocells* m, float iso, const Vec3& org,
                          const Vec3& dir, float tmin, float tmax, float& t_hit) {
  if (!(iso >= g.min_value && iso <= g.max_value)) return false;
  float t0 = tmin, t1 = tmax;
  const Vec3 top(float(g.nx - 1), float(g.ny - 1), float(g.nz - 1));
  if (!clip_to_box(Vec3(0.0f), top, org, dir, t0, t1)) return false;
  const double o[3] = {org.x, org.y, org.z}, d[3] = {dir.x, dir.y, dir.z};
  const int last[3] = {g.nx - 2, g.ny - 2, g.nz - 2};  // the last cell per axis
  return with_voxels(g, [&](const auto& v) {
    double t = t0;
    if (!m) {
      const int zero[3] = {0, 0, 0};
      return walk_cells(v, iso, o, d, zero, last, t, t1, t_hit) == 1;
    }
    // Amanatides and Woo's walk over the macrocells (side M cells); solved cells only inside
    // those whose range holds the isovalue.
    const int M = m->size;
    const int mlast[3] = {m->mx - 1, m->my - 1, m->mz - 1};
    int c[3], step[3];
    double next[3];
    for (int ax = 0; ax < 3; ++ax) {
      const double p = o[ax] + t * d[ax];
      int ci = int(std::floor(p));
      if (d[ax] < 0.0 && double(ci) == p) --ci;  // on a face, moving down: the cell below
      c[ax] = std::clamp(ci, 0, last[ax]) / M;
      step[ax] = d[ax] > 0.0 ? 1 : d[ax] < 0.0 ? -1 : 0;
      next[ax] = d[ax] > 0.0   ? (double((c[ax] + 1) * M) - o[ax]) / d[ax]
                 : d[ax] < 0.0 ? (double(c[ax] * M) - o[ax]) / d[ax]
                               : double(kInfinity);
    }
    while (true) {
      const int ax = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
      const double t_exit = std::min(next[ax], double(t1));
      const size_t mi = m->index(c[0], c[1], c[2]);
      if (m->lo[mi] <= iso && iso <= m->hi[mi]) {
        const int lo[3] = {c[0] * M, c[1] * M, c[2] * M};
        const int hi[3] = {std::min(lo[0] + M - 1, last[0]), std::min(lo[1] + M - 1, last[1]),
                           std::min(lo[2] + M - 1, last[2])};
        double tc = t;
        if (walk_cells(v, iso, o, d, lo, hi, tc, t_exit, t_hit) == 1) return true;
      }
      if (t_exit >= double(t1)) return false;
      t = t_exit;
      c[ax] += step[ax];
      next[ax] = (double((c[ax] + (step[ax] > 0 ? 1 : 0)) * M) - o[ax]) / d[ax];
      if (c[ax] < 0 || c[ax] > mlast[ax]) return false;
    }
  });
}

float trilinear_value(const VolumeGrid& g, const Vec3& p) {
  return with_voxels(g, [&](const auto& v) { return float(cell_value(cell_at<double>(v, g, p))); });
}

Vec3 trilinear_gradient(const VolumeGrid& g, const Vec3& p) {
  return with_voxels(g, [&](const auto& v) { return cell_gradient(cell_at<double>(v, g, p)); });
}

}  // namespace frameless
