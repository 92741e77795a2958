// Lighting volume-shader samples, and the volumes' share of a ray's and a shadow ray's light.
#include "core/shading/volume_lighting.h"

#include <cmath>

#include "core/geometry/shading_frame.h"
#include "core/shading/shading.h"

namespace frameless {

Vec3 ParkerVolumeLighting::light(const Vec3& p, const Vec3& n) const {
  if (n == Vec3(0.0f)) return Vec3(1.0f);
  Vec3 sum = ambient_light(scene_.ambient, p, n);
  for (const Light& l : frame_lights(scene_, frame_)) {
    const Vec3 d = l.kind == LightKind::kDirectional ? -l.direction : l.position - p;
    const float len = glm::length(d);
    if (len > 0.0f) sum += l.color * std::abs(glm::dot(n, d / len));
  }
  return sum;
}

Vec3 through_volumes(const Scene& scene, const DynamicFrame* frame, const Ray& ray, float t_end, const Vec3& behind) {
  if (!scene.see_through_volumes) return behind;
  const ParkerVolumeLighting lighting(scene, frame);
  const VolumeSegment seg = volumes_along(scene, ray, t_end, &lighting);
  return seg.color + seg.transmittance * behind;
}

bool through_volumes(const Scene& scene, const DynamicFrame* frame, const Ray& ray, float t_end, Vec3& radiance,
                     Vec3& beta) {
  const ParkerVolumeLighting lighting(scene, frame);
  const VolumeSegment seg = volumes_along(scene, ray, t_end, &lighting);
  radiance += beta * seg.color;
  beta *= seg.transmittance;
  return max_component(beta) > 0.0f;
}

Vec3 volume_shadow(const Scene& scene, const Ray& ray, bool isosurfaces) {
  if (scene.volumes.empty()) return Vec3(1.0f);
  if (isosurfaces && volumes_occlude(scene, ray)) return Vec3(0.0f);
  return scene.see_through_volumes ? volumes_transmittance(scene, ray) : Vec3(1.0f);
}

Vec3 volume_cone_shadow(const Scene& scene, const Ray& ray, float tan_half) {
  const ShadingFrame f = make_shading_frame(ray.dir);
  Vec3 sum = volume_shadow(scene, ray, true);
  const float r = 0.5f * tan_half;
  const Vec2 offsets[4] = {Vec2(r, 0.0f), Vec2(-r, 0.0f), Vec2(0.0f, r), Vec2(0.0f, -r)};
  for (const Vec2& o : offsets) {
    Ray s = ray;
    s.dir = glm::normalize(f.to_world(Vec3(o.x, o.y, 1.0f)));
    sum += volume_shadow(scene, s, true);
  }
  return 0.2f * sum;
}

}  // namespace frameless
