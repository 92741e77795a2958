// Single-sample soft shadows (seed section 3.2; Parker, Shirley and Smits, UUCS-98-019).
//
// The light subtends a cone of half-angle theta from the shading point. Each occluder gets an
// inner object (the occluder shrunk by the cone's radius theta * t at distance t along the
// shadow ray) and an outer object (grown by the same amount): the offsets grow linearly with the
// distance from the receiver, so the penumbra starts at zero width where occluder and receiver
// touch and straddles the hard shadow's edge. Everything is measured as angles seen from the
// receiver, in units of theta (x = -1 on the inner surface, 0 on the real one, +1 on the outer):
//  * a shadow ray that meets an inner object sees none of the light: s = 0 exactly, and the
//    traversal stops there (the early exit of the any-hit query);
//  * a ray that clears every outer object sees all of it: s = 1 exactly;
//  * in between, s = edge_visibility(x): the fraction of a uniform disk left uncovered by a
//    straight edge at x. The report approximates this "sinusoid" by a Bernstein cubic; the exact
//    form costs one acos per penumbra sample and is what an area light behind a straight edge
//    gives, so the penumbra's gradient matches the area-sampled reference.
// x is the signed angular distance to the outline of everything the ray meets, not of each
// primitive alone: that is how light leaking is handled (the report's concern with touching
// objects). A mesh's interior edges are not outlines: an edge is one only if it is open, or if
// the two triangles sharing it fold to the same side as seen from the receiver (a silhouette).
// Two separate objects that touch still give each other outlines where they meet; when the ray
// is blocked, the nearest outline is therefore confirmed by one any-hit probe just beyond it, and
// an outline whose far side is covered by something else is skipped (no light leaks through the
// seam). Unblocked rays need no probe: the distance to the union is the least distance to a part.
#include "core/shading/soft_shadow.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/geometry/intersect_sphere.h"
#include "core/geometry/intersect_triangle.h"
#include "core/geometry/shading_frame.h"
#include "core/geometry/surface.h"
#include "core/scene/scene_intersect.h"
#include "core/scene/texturing.h"
#include "core/shading/optics.h"

namespace frameless {

float edge_visibility(float x) {
  if (x >= 1.0f) return 1.0f;
  if (x <= -1.0f) return 0.0f;
  const float covered = (std::acos(x) - x * std::sqrt(std::max(0.0f, 1.0f - x * x))) / kPi;
  return std::clamp(1.0f - covered, 0.0f, 1.0f);
}

namespace {

inline float det3(const Vec3& a, const Vec3& b, const Vec3& c) {
  return glm::dot(a, glm::cross(b, c));
}

// An outline within the light's cone: normalized distance x and a direction just beyond it.
struct Outline {
  float x;
  Vec3 probe;
};
constexpr int kMaxOutlines = 4;

// 2-D point on the receiver's image plane at unit depth along the shadow ray.
struct P2 {
  float x, y;
};

// Distance from the origin to segment ab, and the closest point.
inline float segment_distance(P2 a, P2 b, P2& closest) {
  const float ex = b.x - a.x, ey = b.y - a.y;
  const float len2 = ex * ex + ey * ey;
  float t = len2 > 0.0f ? -(a.x * ex + a.y * ey) / len2 : 0.0f;
  t = std::clamp(t, 0.0f, 1.0f);
  closest = {a.x + t * ex, a.y + t * ey};
  return std::sqrt(closest.x * closest.x + closest.y * closest.y);
}

class SoftQuery final : public Accel::ConeVisitor {
 public:
  SoftQuery(const Scene& scene, const ShadowQuery& q, const DynamicFrame* frame)
      : scene_(scene), g_(scene.geometry), q_(q), frame_(frame) {
    const ShadingFrame f = make_shading_frame(q.dir);
    b1_ = f.t;
    b2_ = f.b;
    Ray r;
    r.org = q.org;
    r.dir = q.dir;
    r.tmin = 0.0f;
    r.tmax = q.tmax;
    ray_ = r;
    tri_ray_ = make_triangle_ray(r);
    // Depth range on the shadow ray: the near clip keeps projections finite.
    z_min_ = 1e-6f * std::max(1.0f, max_component(glm::abs(q.org)));
    // Squared tangent with a margin, so rounding never rejects a plane the cone grazes.
    tan2_ = q.tan_half * q.tan_half * 1.01f + 1e-12f;
    cos_theta_ = std::cos(q.half_angle);
    sin_theta_ = std::sin(q.half_angle);
  }

  bool leaf(uint32_t first, uint32_t count) override {
    const uint32_t nt = g_.num_triangles(), fp = g_.first_patch();
    for (uint32_t p = first; p < first + count; ++p) {
      const bool stop = p < nt   ? triangle(p)
                        : p < fp ? sphere(g_.spheres[p - nt], material_of(g_.sphere_material, p - nt), p)
                                 : patch(p - fp);
      if (stop) return false;
    }
    return true;
  }

  // The moving objects of the sample's frame, tested like static spheres. Returns false when
  // s = 0 is certain.
  bool dynamic_objects() {
    if (!frame_) return true;
    for (size_t i = 0; i < frame_->spheres.size(); ++i)
      if (sphere(frame_->spheres[i], frame_->sphere_material[i], kDynamicPrimBase + uint32_t(i)))
        return false;
    return true;
  }

  float finish() {
    if (zero_) return 0.0f;
    if (!blocked_) return edge_visibility(min_out_);
    // Blocked: the nearest outline whose far side is really open decides.
    std::sort(outlines_, outlines_ + n_outlines_,
              [](const Outline& a, const Outline& b) { return a.x < b.x; });
    for (int i = 0; i < n_outlines_; ++i) {
      Ray probe = ray_;
      probe.dir = outlines_[i].probe;
      // With transparent shadows only opaque surfaces close the far side of an outline.
      const bool open = q_.skip_dielectrics
                            ? max_component(shadow_transmittance(scene_, probe, false, frame_)) > 0.0f
                            : !scene_occluded(scene_, frame_, probe);
      if (open) return edge_visibility(-outlines_[i].x);
    }
    return 0.0f;
  }

 private:
  uint16_t material_of(const std::vector<uint16_t>& mats, uint32_t i) const {
    return mats.empty() ? 0 : mats[i];
  }
  // Dielectrics (transparent shadows) and cut-outs are not soft occluders.
  bool skip_material(uint16_t m) const {
    const Material& mat = scene_.materials[m];
    if (q_.skip_dielectrics && mat.cls == MaterialClass::kDielectric) return true;
    return mat.cutout();
  }

  void add_outline(float x, const Vec3& probe) {
    if (!(x < 1.0f)) return;
    if (n_outlines_ < kMaxOutlines) {
      outlines_[n_outlines_++] = {x, probe};
      return;
    }
    int worst = 0;
    for (int i = 1; i < kMaxOutlines; ++i)
      if (outlines_[i].x > outlines_[worst].x) worst = i;
    if (x < outlines_[worst].x) outlines_[worst] = {x, probe};
  }

  Vec3 direction(P2 p) const { return glm::normalize(q_.dir + p.x * b1_ + p.y * b2_); }

  // A spline patch occludes through its shadow grid (kPatchShadowGrid^2 quads on the surface,
  // Geometry::patch_shadow_grid). Its inner edges are not outlines for unblocked rays (the least
  // distance to the union is the least to a part), and blocked rays confirm an outline by a probe
  // against the true patch, so the grid only shapes the penumbra.
  bool patch(uint32_t i) {
    const uint16_t m = material_of(g_.patch_material, i);
    const size_t per = size_t(kPatchShadowGrid + 1) * (kPatchShadowGrid + 1);
    // The receiver's own patch shadows it exactly: its grid's chords would shadow its surface.
    if (skip_material(m) || g_.patch_shadow_grid.size() < (i + 1) * per ||
        q_.receiver == g_.first_patch() + i) {
      // Without a grid (or cut out): the hard shadow of the true surface.
      if (!skip_material(m) && g_.patches[i].occluded(ray_, 0.0f, q_.tmax)) return zero_ = true;
      return false;
    }
    const Vec3* grid = g_.patch_shadow_grid.data() + i * per;
    const int n = kPatchShadowGrid + 1;
    for (int y = 0; y < kPatchShadowGrid; ++y)
      for (int x = 0; x < kPatchShadowGrid; ++x) {
        const Vec3 a = grid[y * n + x], b = grid[y * n + x + 1], c = grid[(y + 1) * n + x + 1],
                   d = grid[(y + 1) * n + x];
        // A quad whose bounding sphere lies outside the light's cone cannot change s (its
        // outlines are at x >= 1): skip it before the projection work. Exact, with a margin.
        const Vec3 centre = 0.25f * (a + b + c + d);
        const float r2 = std::max(std::max(glm::dot(a - centre, a - centre), glm::dot(b - centre, b - centre)),
                                  std::max(glm::dot(c - centre, c - centre), glm::dot(d - centre, d - centre)));
        const Vec3 w = centre - q_.org;
        const float z = glm::dot(w, q_.dir);
        const float perp = glm::length(w - z * q_.dir);
        if (perp * cos_theta_ - z * sin_theta_ > 1.01f * std::sqrt(r2) + 1e-5f * glm::length(w)) continue;
        const Vec3 t0[3] = {a, b, c}, t1[3] = {a, c, d};
        if (corners(t0, nullptr) || corners(t1, nullptr)) return true;
      }
    return false;
  }

  // Returns true when s = 0 is certain (the ray meets an inner object).
  bool triangle(uint32_t i) {
    const uint16_t m = material_of(g_.triangle_material, i);
    if (skip_material(m)) {
      // A cut-out occluder casts the hard shadow of its opaque texels: this triangle alone.
      if (scene_.materials[m].cutout()) {
        const UVec3 t = g_.triangles[i];
        float th, u, v;
        if (intersect_triangle(tri_ray_, g_.positions[t.x], g_.positions[t.y], g_.positions[t.z],
                               0.0f, q_.tmax, th, u, v) &&
            cutout_opaque(scene_, i, ray_, th, u, v))
          return zero_ = true;
      }
      return false;
    }
    const UVec3 t = g_.triangles[i];
    const Vec3 p[3] = {g_.positions[t.x], g_.positions[t.y], g_.positions[t.z]};
    // Across each edge, the neighbour's far vertex (null: an open edge, or no adjacency built).
    const Vec3* opposite[3] = {nullptr, nullptr, nullptr};
    if (!g_.triangle_opposite.empty())
      for (int e = 0; e < 3; ++e) {
        const uint32_t o = g_.triangle_opposite[i][e];
        if (o != kInvalidId) opposite[e] = &g_.positions[o];
      }
    return corners(p, opposite);
  }

  // The cone query against one triangle with corners p, given each edge's neighbour (or null).
  bool corners(const Vec3 p[3], const Vec3* const* opposite) {
    const Vec3 w[3] = {p[0] - q_.org, p[1] - q_.org, p[2] - q_.org};
    // The whole cone on one side of the triangle's plane: it cannot cover any of the light. This
    // drops the receiver's own surface and walls the light faces, the common cases, cheaply.
    {
      const Vec3 n = glm::cross(w[1] - w[0], w[2] - w[0]);
      const float side = -glm::dot(n, w[0]);  // n . (org - p0)
      const float nl = glm::dot(n, q_.dir);
      const float nn = glm::dot(n, n);
      if ((side >= 0.0f) == (nl >= 0.0f) && nl * nl >= tan2_ * (nn - nl * nl)) return false;
    }
    float z[3];
    for (int k = 0; k < 3; ++k) z[k] = glm::dot(w[k], q_.dir);
    const float zmax = q_.tmax;
    if ((z[0] <= z_min_ && z[1] <= z_min_ && z[2] <= z_min_) ||
        (z[0] >= zmax && z[1] >= zmax && z[2] >= zmax))
      return false;
    const float orient = det3(w[0], w[1], w[2]);
    if (!(orient != 0.0f)) return false;  // seen edge-on: covers nothing

    // Clip the triangle to z in [z_min, zmax] (a convex polygon of at most 5 corners) and project
    // it to unit depth; edge_id[k] names the original edge of polygon edge (k, k+1), or -1.
    Vec3 poly[5];
    int edge_id[5];
    int n = 0;
    const bool clip = z[0] <= z_min_ || z[1] <= z_min_ || z[2] <= z_min_ || z[0] >= zmax ||
                      z[1] >= zmax || z[2] >= zmax;
    if (!clip) {
      for (int k = 0; k < 3; ++k) poly[k] = w[k], edge_id[k] = k;
      n = 3;
    } else {
      n = clip_polygon(w, poly, edge_id);
      if (n < 3) return false;
    }
    P2 q[5];
    for (int k = 0; k < n; ++k) {
      // Clipped corners are recomputed: keep their depth at the near clip despite rounding.
      const float d = std::max(glm::dot(poly[k], q_.dir), z_min_);
      q[k] = {glm::dot(poly[k], b1_) / d, glm::dot(poly[k], b2_) / d};
    }
    float u, v, th;
    const bool inside = intersect_triangle(tri_ray_, p[0], p[1], p[2], 0.0f, q_.tmax, th, u, v);
    // Orientation of the projected polygon, to find each edge's outward side.
    float area2 = 0.0f;
    for (int k = 0; k < n; ++k) {
      const P2 a = q[k], b = q[(k + 1) % n];
      area2 += a.x * b.y - a.y * b.x;
    }
    const float out_sign = area2 > 0.0f ? 1.0f : -1.0f;
    const float tan_half = q_.tan_half;
    float min_d = kInfinity;
    for (int k = 0; k < n; ++k) {
      const P2 a = q[k], b = q[(k + 1) % n];
      P2 c;
      const float d = segment_distance(a, b, c);
      min_d = std::min(min_d, d);
      const int e = edge_id[k];
      if (e < 0 || !(d < tan_half)) continue;
      // An interior edge of a mesh is not an outline: the neighbour continues the surface.
      if (opposite && opposite[e]) {
        const float side = det3(w[e], w[(e + 1) % 3], *opposite[e] - q_.org);
        if ((side > 0.0f) != (orient > 0.0f) && side != 0.0f) continue;
      }
      // Outward normal of edge ab in the plane: to the right of a->b for a counter-clockwise
      // polygon, so the probe lands just outside this triangle.
      const float ex = b.x - a.x, ey = b.y - a.y;
      const float len = std::sqrt(ex * ex + ey * ey);
      if (!(len > 0.0f)) continue;
      const float eps = 1e-3f * tan_half;
      const P2 probe{c.x + out_sign * ey / len * eps, c.y - out_sign * ex / len * eps};
      add_outline(d / tan_half, direction(probe));
    }
    if (inside) {
      blocked_ = true;
      // The light's whole disk lies inside this triangle: the ray meets its inner object.
      if (min_d >= tan_half) return zero_ = true;
    } else {
      min_out_ = std::min(min_out_, min_d / tan_half);
    }
    return false;
  }

  // Sutherland-Hodgman clip of triangle w against z >= z_min and z <= zmax.
  int clip_polygon(const Vec3 w[3], Vec3 out[5], int edge_id[5]) const {
    Vec3 a[5], b[5];
    int ida[5], idb[5];
    int na = 3;
    for (int k = 0; k < 3; ++k) a[k] = w[k], ida[k] = k;
    for (int plane = 0; plane < 2; ++plane) {
      int nb = 0;
      for (int k = 0; k < na && nb < 5; ++k) {
        const Vec3 &p0 = a[k], &p1 = a[(k + 1) % na];
        const float d0 = plane == 0 ? glm::dot(p0, q_.dir) - z_min_ : q_.tmax - glm::dot(p0, q_.dir);
        const float d1 = plane == 0 ? glm::dot(p1, q_.dir) - z_min_ : q_.tmax - glm::dot(p1, q_.dir);
        const bool in0 = d0 >= 0.0f, in1 = d1 >= 0.0f;
        if (in0) {
          b[nb] = p0;
          idb[nb++] = ida[k];
        }
        if (in0 != in1 && nb < 5) {
          const float s = d0 / (d0 - d1);
          b[nb] = p0 + s * (p1 - p0);
          // The new corner starts the clip edge when leaving, the old edge when entering.
          idb[nb++] = in0 ? -1 : ida[k];
        }
      }
      na = nb;
      for (int k = 0; k < na; ++k) a[k] = b[k], ida[k] = idb[k];
    }
    for (int k = 0; k < na; ++k) out[k] = a[k], edge_id[k] = ida[k];
    return na;
  }

  bool sphere(const Sphere& s, uint16_t m, uint32_t prim) {
    if (skip_material(m)) {
      // Dynamic objects carry no texture coordinates: a cut-out one casts no shadow.
      if (scene_.materials[m].cutout() && !is_dynamic_prim(prim)) {
        float th;
        if (intersect_sphere(q_.org, q_.dir, s, 0.0f, q_.tmax, th) &&
            cutout_opaque(scene_, prim, ray_, th, 0.0f, 0.0f))
          return zero_ = true;
      }
      return false;
    }
    const Vec3 w = s.center - q_.org;
    const float dist = glm::length(w);
    const float r = std::fabs(s.radius);
    // A receiver inside the sphere (its inner surface) sees no light through it, unless the
    // light is inside too (the shadow ray then never leaves the sphere).
    if (!(dist > r)) {
      float th;
      if (intersect_sphere(q_.org, q_.dir, s, 0.0f, q_.tmax, th)) return zero_ = true;
      return false;
    }
    const float z = glm::dot(w, q_.dir);
    if (z + r <= z_min_ || z - r >= q_.tmax) return false;
    const Vec3 perp = w - z * q_.dir;
    const float perp_len = glm::length(perp);
    // Clear of the outer sphere (gamma >= alpha + theta) by cosines, before any trigonometry:
    // cos gamma <= cos alpha cos theta - sin alpha sin theta, with a margin for rounding.
    const float sin_a = r / dist, cos_a = std::sqrt(std::max(0.0f, 1.0f - sin_a * sin_a));
    if (z < (cos_a * cos_theta_ - sin_a * sin_theta_) * dist - 1e-5f * dist) {
      min_out_ = std::min(min_out_, 1.0f);
      return false;
    }
    const float gamma = std::atan2(perp_len, z);  // angle from the ray to the centre
    const float alpha = std::asin(std::min(1.0f, r / dist));  // the outline's angular radius
    const float x = (gamma - alpha) / q_.half_angle;          // < 0: the ray meets the sphere
    float th;
    const bool inside = intersect_sphere(q_.org, q_.dir, s, 0.0f, q_.tmax, th);
    if (x < 1.0f && x > -1.0f) {
      // Probe just outside the outline, on the far side from the centre.
      const Vec3 u = perp_len > 0.0f ? perp / perp_len : b1_;
      const float phi = (alpha - gamma) + 1e-3f * q_.half_angle;  // rotate away from the centre
      add_outline(std::fabs(x), std::cos(phi) * q_.dir - std::sin(phi) * u);
    }
    if (inside) {
      blocked_ = true;
      if (x <= -1.0f) return zero_ = true;
    } else {
      min_out_ = std::min(min_out_, std::max(x, 0.0f));
    }
    return false;
  }

  const Scene& scene_;
  const Geometry& g_;
  const ShadowQuery& q_;
  const DynamicFrame* frame_;
  Vec3 b1_, b2_;
  Ray ray_;
  TriangleRay tri_ray_;
  float z_min_;
  float tan2_;
  float cos_theta_, sin_theta_;
  bool blocked_ = false;
  bool zero_ = false;
  float min_out_ = kInfinity;  // least normalized distance to a part the ray misses
  Outline outlines_[kMaxOutlines];
  int n_outlines_ = 0;
};

}  // namespace

float soft_visibility(const Scene& scene, const ShadowQuery& q, const DynamicFrame* frame) {
  if (!(q.tan_half > 0.0f) || !(q.half_angle > 0.0f)) {
    Ray r;
    r.org = q.org;
    r.dir = q.dir;
    r.tmax = q.tmax;
    return scene_occluded(scene, frame, r) ? 0.0f : 1.0f;
  }
  SoftQuery query(scene, q, frame);
  Ray r;
  r.org = q.org;
  r.dir = q.dir;
  r.tmax = q.tmax;
  if (!query.dynamic_objects()) return 0.0f;
  // Instanced geometry is outside the cone query: it shadows the axis (a hard shadow).
  if (scene.accel.occluded_instances(r, frame_instances(frame))) return 0.0f;
  if (!scene.accel.visit_cone(r, q.tan_half, query)) return 0.0f;
  return query.finish();
}

Vec3 beam_visibility(const Scene& scene, const ShadowQuery& q, const DynamicFrame* frame) {
  // Four directions, each standing for a quarter of the cone's disc: at sqrt(1/2) of its radius
  // (the circle splitting the disc's area in halves), at 45, 135, 225 and 315 degrees.
  const ShadingFrame axes = make_shading_frame(q.dir);
  const float t = 0.5f * q.tan_half;  // each coordinate: sqrt(1/2) of sqrt(1/2) of the radius
  const Vec2 pattern[4] = {Vec2(t, t), Vec2(-t, t), Vec2(-t, -t), Vec2(t, -t)};
  Ray rays[4];
  for (int k = 0; k < 4; ++k) {
    rays[k].org = q.org;
    rays[k].dir = glm::normalize(q.dir + pattern[k].x * axes.t + pattern[k].y * axes.b);
    rays[k].tmax = q.tmax;
  }
  Vec3 visible(0.0f);
  if (q.skip_dielectrics) {
    for (const Ray& r : rays) visible += shadow_transmittance(scene, r, false, frame);
  } else if (frame || !scene.volumes.empty()) {
    for (const Ray& r : rays) visible += scene_occluded(scene, frame, r) ? Vec3(0.0f) : Vec3(1.0f);
  } else {
    bool blocked[4];
    scene.accel.occluded_packet(rays, 4, blocked);
    for (bool b : blocked) visible += b ? Vec3(0.0f) : Vec3(1.0f);
  }
  return 0.25f * visible;
}

Vec3 area_visibility(const Scene& scene, const ShadowQuery& q, int samples, Rng& rng,
                     const DynamicFrame* frame) {
  samples = std::max(1, samples);
  const ShadingFrame axes = make_shading_frame(q.dir);
  const Vec3 b1 = axes.t, b2 = axes.b;
  const float cos_max = std::cos(q.half_angle);
  // Stratified over the cone's solid angle in cos(theta) and, through a fixed co-prime
  // permutation of the strata, in azimuth (a Latin hypercube: unbiased for any count).
  int step = 7;
  while (std::gcd(step, samples) != 1) ++step;
  Vec3 visible(0.0f);
  for (int k = 0; k < samples; ++k) {
    const float u1 = (float(k) + rng.next_float()) / float(samples);
    const float u2 = (float((k * step) % samples) + rng.next_float()) / float(samples);
    const float cos_t = 1.0f - u1 * (1.0f - cos_max);
    const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
    const float phi = 2.0f * kPi * u2;
    Ray r;
    r.org = q.org;
    r.dir = glm::normalize(cos_t * q.dir + sin_t * (std::cos(phi) * b1 + std::sin(phi) * b2));
    r.tmax = q.tmax;
    if (q.skip_dielectrics) visible += shadow_transmittance(scene, r, false, frame);
    else if (!scene_occluded(scene, frame, r)) visible += Vec3(1.0f);
  }
  return visible / float(samples);
}

}  // namespace frameless
