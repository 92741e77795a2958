// TEMPORARY brute-force placeholder, to be replaced by the BVH.
#include "core/accel.h"

namespace frameless {

struct Accel::Impl {
  const Geometry* geom = nullptr;
  AccelStats stats;
};

Accel::Accel() : impl_(std::make_unique<Impl>()) {}
Accel::~Accel() = default;
Accel::Accel(Accel&&) noexcept = default;
Accel& Accel::operator=(Accel&&) noexcept = default;

void Accel::build(Geometry& geom, const AccelConfig&) { impl_->geom = &geom; }

static bool hit_triangle(const Geometry& g, uint32_t i, const Ray& r, float tmax, float& t, float& u,
                         float& v) {
  const UVec3 tri = g.triangles[i];
  const Vec3 p0 = g.positions[tri.x], e1 = g.positions[tri.y] - p0, e2 = g.positions[tri.z] - p0;
  const Vec3 pv = glm::cross(r.dir, e2);
  const float det = glm::dot(e1, pv);
  if (det == 0.0f) return false;
  const float inv = 1.0f / det;
  const Vec3 tv = r.org - p0;
  u = glm::dot(tv, pv) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  const Vec3 qv = glm::cross(tv, e1);
  v = glm::dot(r.dir, qv) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
  t = glm::dot(e2, qv) * inv;
  return t >= r.tmin && t <= tmax;
}

static bool hit_sphere(const Sphere& s, const Ray& r, float tmax, float& t) {
  const Vec3 oc = r.org - s.center;
  const float b = glm::dot(oc, r.dir), c = glm::dot(oc, oc) - s.radius * s.radius;
  const float disc = b * b - c;
  if (disc < 0.0f) return false;
  const float sq = std::sqrt(disc);
  t = -b - sq;
  if (t < r.tmin) t = -b + sq;
  return t >= r.tmin && t <= tmax;
}

bool Accel::intersect(const Ray& ray, Hit& hit) const {
  const Geometry& g = *impl_->geom;
  float tmax = ray.tmax;
  bool found = false;
  for (uint32_t i = 0; i < g.num_triangles(); ++i) {
    float t, u, v;
    if (hit_triangle(g, i, ray, tmax, t, u, v)) {
      tmax = t, hit.t = t, hit.u = u, hit.v = v, hit.prim = i, found = true;
    }
  }
  for (uint32_t i = 0; i < g.num_spheres(); ++i) {
    float t;
    if (hit_sphere(g.spheres[i], ray, tmax, t)) {
      tmax = t, hit.t = t, hit.prim = g.num_triangles() + i, found = true;
    }
  }
  return found;
}

bool Accel::occluded(const Ray& ray) const {
  Hit h;
  return intersect(ray, h);
}

const AccelStats& Accel::stats() const { return impl_->stats; }

}  // namespace frameless
