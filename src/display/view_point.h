// A displayed pixel's point in 8 bytes (display thread only): where its content lies, relative to
// the display's camera and to the pixel that holds it, instead of a 16-byte world position.
// Reprojection reads and writes every pixel's point at each camera change, so the point's size is
// bandwidth (benchmarks.md, section 26). The engine's own points stay in world space (pixel_points.h).
#pragma once
#include <cstdint>
#include <limits>

#include "core/base/fused_float.h"
#include "core/scene/camera.h"
#include "core/shading/render_sample.h"
#include "frameless/pixel_points.h"

namespace frameless {

// camera_ray inverted, with its constants folded: for d = point - eye, z = w.d, the pixel
// position is (cx + x.d / z, cy - y.d / z) (sx = (2 px / W - 1) tan_half aspect, sy = (1 - 2 py / H) tan_half).
struct Projector {
  explicit Projector(const CameraBasis& b)
      : eye(b.eye), w(b.w), x(b.u * (0.5f * float(b.width) / (b.tan_half * b.aspect))),
        y(b.v * (0.5f * float(b.height) / b.tan_half)), cx(0.5f * float(b.width)),
        cy(0.5f * float(b.height)), width(float(b.width)), height(float(b.height)) {}
  Vec3 eye, w, x, y;
  float cx, cy, width, height;
  // Where `point` appears: continuous pixel position and its depth along the view axis
  // (+infinity for the sky, whose position is a direction). False behind the eye or outside.
  bool operator()(const ScenePoint& point, float& px, float& py, float& depth) const {
    if (point.object == kPointNone) return false;
    const bool sky = point.object == kPointSky;
    const Vec3 d = sky ? point.p : point.p - eye;
    // Explicitly fused (core/base/fused_float.h), so the splat's vector form rounds alike.
    const float z = dot_exact(d, w);
    if (!(z > 0.0f)) return false;  // behind the eye (or NaN)
    const float inv = 1.0f / z;
    px = fmadd(dot_exact(d, x), inv, cx);
    py = fmadd(-dot_exact(d, y), inv, cy);
    depth = sky ? std::numeric_limits<float>::infinity() : z;
    return px >= 0.0f && px < width && py >= 0.0f && py < height;
  }
};

inline bool project_point(const CameraBasis& to, const ScenePoint& point, float& px, float& py, float& depth) {
  return Projector(to)(point, px, py, depth);
}

// What a point is, as reprojection needs to know it: nothing there, the sky (a direction), a
// static surface, or a surface that may move (a dynamic object or an instance).
enum ViewKind : uint32_t { kViewNone = 0, kViewSky = 1, kViewStatic = 2, kViewMoving = 3 };

inline uint32_t view_kind_of(uint32_t object) {
  if (object == kPointNone) return kViewNone;
  if (object == kPointSky) return kViewSky;
  return point_may_move(object) ? kViewMoving : kViewStatic;
}

// The point's depth along the camera's view axis (+infinity for the sky) and where inside its
// pixel it projects, in 1/32768 of a pixel (error at most 1/65536: a walk of 10^4 moves drifts
// about 1/650 of a pixel), with its kind in the top two bits.
struct ViewPoint {
  float depth = 0.0f;
  uint32_t bits = 0;  // x fraction | y fraction << 15 | kind << 30
};
static_assert(sizeof(ViewPoint) == 8, "eight pixels' points per cache line");

inline constexpr uint32_t kViewFractionBits = 15;
inline constexpr uint32_t kViewFractionMask = (1u << kViewFractionBits) - 1u;
inline constexpr float kViewFractionStep = 0x1p-15f;
inline constexpr float kViewFractionScale = 32768.0f;  // 1 / kViewFractionStep
inline constexpr uint32_t kViewKindShift = 30;
// A pixel's centre: where reprojection puts a copy of a neighbour's content.
inline constexpr uint32_t kViewCentre = (1u << 14) | (1u << 14) << kViewFractionBits;

inline uint32_t view_kind(uint32_t bits) { return bits >> kViewKindShift; }

// The bits of a point projecting at continuous pixel position (px, py) (both >= 0): the
// fractions of px and py past their pixel's corner (exact: px - trunc(px) rounds nothing, and
// times 2^15 neither).
inline uint32_t view_bits(float px, float py, uint32_t kind) {
  const uint32_t qx = uint32_t((px - float(int(px))) * kViewFractionScale);
  const uint32_t qy = uint32_t((py - float(int(py))) * kViewFractionScale);
  return qx | qy << kViewFractionBits | kind << kViewKindShift;
}

// The continuous position of fraction q inside pixel column (or row) i.
inline float view_position(uint32_t i, uint32_t q) {
  return fmadd(float(q) + 0.5f, kViewFractionStep, float(i));  // the product is exact: one rounding
}

// Moves points from camera `a`'s view to camera `b`'s: for a point at pixel position (X, Y) of a
// and depth z there, b's view coordinates are t + z * (k0 + k1 X + k2 Y) per axis (w: depth; x,
// y: Projector's scaled axes), and the sky's (a direction) k0 + k1 X + k2 Y.
struct ViewMove {
  ViewMove(const CameraBasis& a, const CameraBasis& b) : to(b) {
    // camera_direction(a, X, Y) = a.w + sx a.u + sy a.v with sx = ax X + bx, sy = ay Y + by.
    const float ax = 2.0f / float(a.width) * a.tan_half * a.aspect, bx = -a.tan_half * a.aspect;
    const float ay = -2.0f / float(a.height) * a.tan_half, by = a.tan_half;
    const Vec3 axes[3] = {to.w, to.x, to.y};
    for (int i = 0; i < 3; ++i) {
      const Vec3& e = axes[i];
      const float du = glm::dot(a.u, e), dv = glm::dot(a.v, e);
      k0[i] = glm::dot(a.w, e) + bx * du + by * dv;
      k1[i] = ax * du;
      k2[i] = ay * dv;
      t[i] = glm::dot(a.eye - b.eye, e);
    }
  }
  Projector to;
  float k0[3], k1[3], k2[3], t[3];

  // Where point `v` held by pixel (x, y) of a appears in b: continuous pixel position and depth
  // (+infinity for the sky). False for no point, behind the eye or outside. The vector splats
  // (reproject.cpp, reproject_avx2.cpp) do these operations in this order.
  bool operator()(const ViewPoint& v, uint32_t x, uint32_t y, float& px, float& py, float& depth) const {
    const uint32_t kind = view_kind(v.bits);
    if (kind == kViewNone) return false;
    const float X = view_position(x, v.bits & kViewFractionMask);
    const float Y = view_position(y, (v.bits >> kViewFractionBits) & kViewFractionMask);
    float c[3];
    for (int i = 0; i < 3; ++i) {
      const float k = fmadd(k2[i], Y, fmadd(k1[i], X, k0[i]));
      c[i] = kind == kViewSky ? k : fmadd(v.depth, k, t[i]);
    }
    if (!(c[0] > 0.0f)) return false;  // behind the eye (or NaN)
    const float inv = 1.0f / c[0];
    px = fmadd(c[1], inv, to.cx);
    py = fmadd(-c[2], inv, to.cy);
    depth = kind == kViewSky ? std::numeric_limits<float>::infinity() : c[0];
    return px >= 0.0f && px < to.width && py >= 0.0f && py < to.height;
  }
};

// A world point as camera b's pixel `pixel` holds it (kind none when it projects nowhere).
inline ViewPoint to_view(const CameraBasis& b, const ScenePoint& p, size_t& pixel) {
  float px, py, depth;
  if (!project_point(b, p, px, py, depth)) return {};
  pixel = size_t(int(py)) * size_t(b.width) + size_t(int(px));
  return {depth, view_bits(px, py, view_kind_of(p.object))};
}

// The world point pixel `pixel` of camera b holds (a direction for the sky).
inline ScenePoint from_view(const CameraBasis& b, const ViewPoint& v, size_t pixel) {
  const uint32_t kind = view_kind(v.bits);
  if (kind == kViewNone) return {};
  const float X = view_position(uint32_t(pixel % size_t(b.width)), v.bits & kViewFractionMask);
  const float Y = view_position(uint32_t(pixel / size_t(b.width)), (v.bits >> kViewFractionBits) & kViewFractionMask);
  const Vec3 dir = camera_direction(b, X, Y);
  const uint32_t object = kind == kViewSky ? kPointSky : kind == kViewMoving ? kPointDynamic : kPointStatic;
  return {kind == kViewSky ? dir : b.eye + v.depth * dir, object};
}

}  // namespace frameless
