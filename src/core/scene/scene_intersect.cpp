// Per-ray queries over the whole scene: the static structure plus the moving objects of a frame.
#include "core/scene/scene_intersect.h"

#include "core/accel/instance.h"
#include "core/accel/instance_top.h"
#include "core/geometry/intersect_sphere.h"
#include "core/scene/scene_volumes.h"

namespace frameless {

bool scene_intersect(const Scene& scene, const DynamicFrame* frame, const Ray& ray, Hit& hit) {
  if (!scene.accel.intersect(ray, hit, frame_instances(frame))) hit = Hit{};
  return merge_nonstatic_hits(scene, frame, ray, hit);
}

bool merge_nonstatic_hits(const Scene& scene, const DynamicFrame* frame, const Ray& ray, Hit& hit) {
  if (!scene.volumes.empty()) merge_volume_hits(scene, ray, hit);
  return merge_dynamic_hit(frame, ray, hit);
}

bool merge_dynamic_hit(const DynamicFrame* frame, const Ray& ray, Hit& hit) {
  bool found = hit.valid();
  if (!frame) return found;
  float tmax = found ? hit.t : ray.tmax;
  const size_t n = frame->spheres.size();
  for (size_t i = 0; i < n; ++i) {
    float t;
    if (intersect_sphere(ray.org, ray.dir, frame->spheres[i], ray.tmin, tmax, t)) {
      tmax = t;
      hit.t = t;
      hit.u = hit.v = 0.0f;
      hit.prim = kDynamicPrimBase + uint32_t(i);
      hit.inst = kInvalidId;
      found = true;
    }
  }
  return found;
}

bool scene_occluded(const Scene& scene, const DynamicFrame* frame, const Ray& ray) {
  if (frame) {  // a handful of spheres first: cheaper than the BVH walk
    for (const Sphere& s : frame->spheres) {
      float t;
      if (intersect_sphere(ray.org, ray.dir, s, ray.tmin, ray.tmax, t)) return true;
    }
  }
  if (!scene.volumes.empty() && volumes_occlude(scene, ray)) return true;
  return scene.accel.occluded(ray, frame_instances(frame));
}

SurfacePoint scene_surface_point(const Scene& scene, const DynamicFrame* frame, const Ray& ray,
                                 const Hit& hit) {
  if (is_volume_prim(hit.prim)) return volume_surface_point(scene, ray, hit);
  if (hit.inst != kInvalidId)
    return instance_surface_point(*scene.accel.top_in_use(frame_instances(frame)), ray, hit);
  if (!is_dynamic_prim(hit.prim) || !frame) return surface_point(scene.geometry, ray, hit);
  const uint32_t i = hit.prim - kDynamicPrimBase;
  SurfacePoint sp = sphere_surface_point(frame->spheres[i], frame->sphere_material[i], ray, hit.t);
  sp.prim = hit.prim;
  return sp;
}

}  // namespace frameless
