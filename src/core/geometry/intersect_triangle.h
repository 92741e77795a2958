// Watertight ray/triangle intersection (Woop, Benthin, Wald 2013, JCGT 2(1)); any thread.
#pragma once
#include <cmath>
#include <utility>

#include "core/base/fused_float.h"
#include "core/geometry/ray.h"

namespace frameless {

// Per-ray constants of the watertight test: the axis permutation that makes the largest direction
// component z, and the shear that maps the ray onto +z.
struct TriangleRay {
  float ox = 0.0f, oy = 0.0f, oz = 0.0f;  // origin, permuted
  int kx = 0, ky = 1, kz = 2;
  float sx = 0.0f, sy = 0.0f, sz = 1.0f;
};

[[gnu::always_inline]]
inline TriangleRay make_triangle_ray(const Ray& ray) {
  TriangleRay r;
  const Vec3 a = glm::abs(ray.dir);
  r.kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
  r.kx = r.kz == 2 ? 0 : r.kz + 1;
  r.ky = r.kx == 2 ? 0 : r.kx + 1;
  // Keep the winding of the sheared triangle independent of the ray direction's sign.
  if (ray.dir[r.kz] < 0.0f) std::swap(r.kx, r.ky);
  const float* d = &ray.dir.x;
  const float* o = &ray.org.x;
  r.sx = d[r.kx] / d[r.kz];
  r.sy = d[r.ky] / d[r.kz];
  r.sz = 1.0f / d[r.kz];
  r.ox = o[r.kx], r.oy = o[r.ky], r.oz = o[r.kz];
  return r;
}

// Ray against triangle (p0, p1, p2) over [tmin, tmax]. On a hit returns true and sets t and the
// barycentrics b1 (of p1) and b2 (of p2). Edges shared by two triangles are never missed by both.
[[gnu::always_inline]]
inline bool intersect_triangle(const TriangleRay& r, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                               float tmin, float tmax, float& t, float& b1, float& b2) {
  // Coordinates relative to the origin, permuted; indexing the vertices in memory (not a
  // computed Vec3) keeps everything in registers.
  const float *q0 = &p0.x, *q1 = &p1.x, *q2 = &p2.x;
  const float a_x = q0[r.kx] - r.ox, a_y = q0[r.ky] - r.oy, a_z = q0[r.kz] - r.oz;
  const float b_x = q1[r.kx] - r.ox, b_y = q1[r.ky] - r.oy, b_z = q1[r.kz] - r.oz;
  const float c_x = q2[r.kx] - r.ox, c_y = q2[r.ky] - r.oy, c_z = q2[r.kz] - r.oz;
  // Sheared coordinates and 2D edge functions with a fixed rounding sequence
  // (core/base/fused_float.h): a shared edge's function must be the exact negative of its
  // neighbour's.
  const float ax = fmadd(-r.sx, a_z, a_x), ay = fmadd(-r.sy, a_z, a_y);
  const float bx = fmadd(-r.sx, b_z, b_x), by = fmadd(-r.sy, b_z, b_y);
  const float cx = fmadd(-r.sx, c_z, c_x), cy = fmadd(-r.sy, c_z, c_y);
  float u = mul_exact(cx, by) - mul_exact(cy, bx);
  float v = mul_exact(ax, cy) - mul_exact(ay, cx);
  float w = mul_exact(bx, ay) - mul_exact(by, ax);
  // Exactly on an edge in single precision: decide in double so neighbours agree (paper, sec. 4).
  if (u == 0.0f || v == 0.0f || w == 0.0f) {
    u = float(double(cx) * double(by) - double(cy) * double(bx));
    v = float(double(ax) * double(cy) - double(ay) * double(cx));
    w = float(double(bx) * double(ay) - double(by) * double(ax));
  }
  // One branch for all rejections (mixed edge signs, zero determinant, outside the interval):
  // the early-outs of the paper mispredict about half the time in a BVH leaf.
  const bool has_neg = (u < 0.0f) | (v < 0.0f) | (w < 0.0f);
  const bool has_pos = (u > 0.0f) | (v > 0.0f) | (w > 0.0f);
  const float det = u + v + w;
  const float az = mul_exact(r.sz, a_z), bz = mul_exact(r.sz, b_z), cz = mul_exact(r.sz, c_z);
  const float tt = fmadd(u, az, fmadd(v, bz, mul_exact(w, cz)));
  // Compare the scaled distance against the interval without dividing (sign of det folded in;
  // negation is exact, so this equals comparing tt with tmin * det and tmax * det).
  const float adet = std::abs(det);
  const float stt = det < 0.0f ? -tt : tt;
  const bool in_range = int(stt >= mul_exact(tmin, adet)) & int(stt <= mul_exact(tmax, adet));
  if (!(!(has_neg & has_pos) & (det != 0.0f) & in_range)) return false;
  const float inv = 1.0f / det;
  t = mul_exact(tt, inv);
  b1 = mul_exact(v, inv);
  b2 = mul_exact(w, inv);
  return true;
}

}  // namespace frameless
