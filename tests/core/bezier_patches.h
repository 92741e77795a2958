// Bicubic Bézier test patches, the teapot's, and a reference evaluation (bezier, patch_surface).
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "core/base/error.h"
#include "core/geometry/bezier.h"
#include "core/io/patch_io.h"

namespace frameless {
namespace test_util {

// The teapot's 32 patches (apt-get install povray-examples).
inline const char* const kTeapot = "/usr/share/doc/povray/examples/advanced/teapot/teapot.inc";

using DVec3 = glm::dvec3;

// Reference evaluation, independent of bezier.cpp: de Casteljau in double, rows along u first.
inline DVec3 casteljau(DVec3 c[4], double t) {
  for (int k = 3; k > 0; --k)
    for (int i = 0; i < k; ++i) c[i] = glm::mix(c[i], c[i + 1], t);
  return c[0];
}

inline DVec3 ref_point(const BezierPatch& p, double u, double v) {
  DVec3 col[4];
  for (int i = 0; i < 4; ++i) {
    DVec3 row[4] = {DVec3(p.p[4 * i]), DVec3(p.p[4 * i + 1]), DVec3(p.p[4 * i + 2]), DVec3(p.p[4 * i + 3])};
    col[i] = casteljau(row, u);
  }
  return casteljau(col, v);
}

// Planar, with unevenly spaced control points: a nonlinear parametrisation of a flat quad.
inline BezierPatch flat_patch() {
  const Vec3 o(0.3f, -0.2f, 1.0f), e1(1.0f, 0.2f, 0.3f), e2(-0.1f, 1.0f, 0.5f);
  const float a[4] = {0.0f, 0.5f, 1.9f, 3.0f}, b[4] = {0.0f, 1.3f, 1.7f, 3.0f};
  BezierPatch p;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) p.p[4 * i + j] = o + a[j] * e1 + (b[i] + 0.1f * a[j]) * e2;
  return p;
}

// A height field over 3 x 3 with strong bumps: rays can cross it several times.
inline BezierPatch curved_patch() {
  const float h[16] = {0.0f, 0.5f, -0.3f, 0.2f, 0.4f, 1.5f, -1.0f, 0.1f,
                       -0.2f, -1.2f, 1.3f, 0.3f, 0.1f, 0.3f, -0.4f, 0.0f};
  BezierPatch p;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) p.p[4 * i + j] = Vec3(float(j), float(i), h[4 * i + j]);
  return p;
}

// Half a bent tube: most rays through it cross it twice, so the closest crossing matters.
inline BezierPatch tube_patch() {
  const float x[4] = {1.0f, 1.0f, -1.0f, -1.0f}, y[4] = {0.0f, 1.33f, 1.33f, 0.0f};
  BezierPatch p;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) p.p[4 * i + j] = Vec3(x[j] + 0.2f * float(i * i), y[j], 1.2f * float(i));
  return p;
}

// A quarter of a cap of revolution whose row 0 collapses to the pole (0,0,1), like the teapot's
// lid and bottom: u runs clockwise around the axis (seen from above), v from the pole outward and
// down, so du x dv points outward and up, and is (0,0,1) at the pole.
inline BezierPatch cap_patch() {
  const float r[4] = {0.0f, 0.8f, 1.2f, 1.3f}, z[4] = {1.0f, 1.0f, 0.6f, 0.0f};
  const float k = 0.552f;  // circle approximation
  BezierPatch p;
  for (int i = 0; i < 4; ++i) {
    p.p[4 * i + 0] = Vec3(r[i], 0.0f, z[i]);
    p.p[4 * i + 1] = Vec3(r[i], -k * r[i], z[i]);
    p.p[4 * i + 2] = Vec3(k * r[i], -r[i], z[i]);
    p.p[4 * i + 3] = Vec3(0.0f, -r[i], z[i]);
  }
  return p;
}

inline Result<std::vector<BezierPatch>> teapot() { return load_bicubic_patches(kTeapot); }

}  // namespace test_util
}  // namespace frameless
