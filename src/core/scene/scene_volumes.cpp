// Rays against a scene's volumes: isosurfaces as surfaces, the others composited along the ray.
#include "core/scene/scene_volumes.h"

#include <algorithm>

#include "core/volume/isosurface.h"

namespace frameless {
namespace {

// The part [t0, t1] of the ray inside the volume's world bounds; false when it misses.
inline bool in_bounds(const VolumeObject& v, const Ray& ray, float& t0, float& t1) {
  return clip_to_box(v.lo, v.hi, ray.org, ray.dir, t0, t1);
}

// A volume-shader sample's light, from index space to the world.
struct IndexLighting final : SampleLighting {
  const VolumeObject& v;
  const VolumeLighting& world;
  IndexLighting(const VolumeObject& vol, const VolumeLighting& l) : v(vol), world(l) {}
  Vec3 light(const Vec3& p, const Vec3& g) const override {
    const Vec3 n = v.normal_to_world * g;
    const float len = glm::length(n);
    return world.light(v.to_world.point(p), len > 0.0f ? n / len : Vec3(0.0f));
  }
};

}  // namespace

bool merge_volume_hits(const Scene& scene, const Ray& ray, Hit& hit) {
  bool found = hit.valid();
  float tmax = found ? hit.t : ray.tmax;
  for (size_t i = 0; i < scene.volumes.size(); ++i) {
    const VolumeObject& v = scene.volumes[i];
    if (v.mode != VolumeMode::kIsosurface) continue;
    float a = ray.tmin, b = tmax;
    if (!in_bounds(v, ray, a, b)) continue;
    const Vec3 o = v.to_index.point(ray.org), d = v.to_index.vector(ray.dir);
    for (size_t k = 0; k < v.isovalues.size(); ++k) {
      float t;
      if (intersect_isosurface(*v.grid, v.cells.get(), v.isovalues[k], o, d, a, b, t) && t < tmax) {
        tmax = b = t;
        hit.t = t;
        hit.prim = kVolumePrimBase + uint32_t(i) * kMaxIsovalues + uint32_t(k);
        hit.inst = kInvalidId;
        hit.u = hit.v = 0.0f;
        found = true;
      }
    }
  }
  return found;
}

bool volumes_occlude(const Scene& scene, const Ray& ray) {
  for (const VolumeObject& v : scene.volumes) {
    if (v.mode != VolumeMode::kIsosurface) continue;
    float a = ray.tmin, b = ray.tmax;
    if (!in_bounds(v, ray, a, b)) continue;
    const Vec3 o = v.to_index.point(ray.org), d = v.to_index.vector(ray.dir);
    for (float iso : v.isovalues) {
      float t;
      if (intersect_isosurface(*v.grid, v.cells.get(), iso, o, d, a, b, t)) return true;
    }
  }
  return false;
}

SurfacePoint volume_surface_point(const Scene& scene, const Ray& ray, const Hit& hit) {
  const uint32_t id = hit.prim - kVolumePrimBase;
  const VolumeObject& v = scene.volumes[id / kMaxIsovalues];
  const uint32_t k = id % kMaxIsovalues;
  SurfacePoint sp;
  sp.p = ray.org + hit.t * ray.dir;
  const Vec3 g = v.normal_to_world * trilinear_gradient(*v.grid, v.to_index.point(sp.p));
  const float len = glm::length(g);
  // Out of the inside: against the gradient when the inside holds the larger values.
  const Vec3 out = len > 0.0f ? (v.inside_above ? -g : g) / len : -ray.dir;
  sp.front_face = glm::dot(out, ray.dir) < 0.0f;
  sp.ng = sp.front_face ? out : -out;
  sp.ns = sp.ng;
  sp.material = v.iso_materials[k];
  sp.prim = hit.prim;
  sp.scale = v.scale;
  return sp;
}

VolumeSegment volumes_along(const Scene& scene, const Ray& ray, float t_end, const VolumeLighting* lighting) {
  VolumeSegment total;
  // Front to back by where the ray enters each (overlapping volumes composite approximately).
  struct Span {
    const VolumeObject* v;
    float a, b;
  };
  Span spans[8];
  int n = 0;
  for (const VolumeObject& v : scene.volumes) {
    if (v.mode == VolumeMode::kIsosurface || n == 8) continue;
    float a = ray.tmin, b = std::min(t_end, ray.tmax);
    if (in_bounds(v, ray, a, b) && b > a) spans[n++] = {&v, a, b};
  }
  for (int i = 1; i < n; ++i)  // insertion sort: a handful of spans
    for (int k = i; k > 0 && spans[k].a < spans[k - 1].a; --k) std::swap(spans[k], spans[k - 1]);
  for (int i = 0; i < n && total.transmittance > 0.0f; ++i) {
    const VolumeObject& v = *spans[i].v;
    const Vec3 o = v.to_index.point(ray.org), d = v.to_index.vector(ray.dir);
    VolumeSegment seg;
    if (v.mode == VolumeMode::kMip) {
      float value;
      if (!march_maximum(v.march(), o, d, spans[i].a, spans[i].b, value, &seg.samples)) continue;
      Vec3 c;
      float alpha;
      v.tf->lookup(value, c, alpha);
      seg.color = alpha * c;  // the brightest sample, over what lies behind by its opacity
      seg.transmittance = 1.0f - alpha;
    } else {
      if (lighting && v.shade) {
        const IndexLighting light(v, *lighting);
        seg = march_volume(v.march(), o, d, spans[i].a, spans[i].b, &light);
      } else {
        seg = march_volume(v.march(), o, d, spans[i].a, spans[i].b, nullptr);
      }
    }
    total.color += total.transmittance * seg.color;
    total.transmittance *= seg.transmittance;
    total.samples += seg.samples;
  }
  return total;
}

Vec3 volumes_transmittance(const Scene& scene, const Ray& ray) {
  Vec3 t(1.0f);
  for (const VolumeObject& v : scene.volumes) {
    if (v.mode != VolumeMode::kDirect) continue;
    float a = ray.tmin, b = ray.tmax;
    if (!in_bounds(v, ray, a, b) || !(b > a)) continue;
    t *= march_transmittance(v.march(), v.to_index.point(ray.org), v.to_index.vector(ray.dir), a, b);
    if (max_component(t) <= 0.0f) return Vec3(0.0f);
  }
  return t;
}

}  // namespace frameless
