// Lighting volume-shader samples, and the volumes' share of a ray's and a shadow ray's light.
#include "core/shading/volume_lighting.h"

#include <algorithm>
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

namespace {

// The see-through part of [tmin, t_end]: volume-shader and MIP volumes, and lightfields composited
// in front-to-back order of their boxes' entries (the volumes between them split at each entry).
VolumeSegment see_through_along(const Scene& scene, const DynamicFrame* frame, const Ray& ray, float t_end) {
  const ParkerVolumeLighting lighting(scene, frame);
  if (scene.lightfields.empty()) return volumes_along(scene, ray, t_end, &lighting);
  constexpr int kMaxLayers = 8;  // nearest first; a ray behind eight lightfields sees no more
  LightfieldHit layers[kMaxLayers];
  int n = 0;
  for (const LightfieldObject& o : scene.lightfields) {
    LightfieldHit h;
    if (!lightfield_along(o, ray, t_end, h)) continue;
    int k = std::min(n, kMaxLayers - 1);
    if (n == kMaxLayers && h.t >= layers[k].t) continue;
    for (; k > 0 && layers[k - 1].t > h.t; --k) layers[k] = layers[k - 1];
    layers[k] = h;
    n = std::min(n + 1, kMaxLayers);
  }
  // n lightfield layers split the ray into n + 1 stretches of volumes, composited front to back.
  VolumeSegment total;
  Ray part = ray;
  const auto add = [&total](const Vec3& color, float transmittance) {
    total.color += total.transmittance * color;
    total.transmittance *= transmittance;
  };
  for (int k = 0; k <= n; ++k) {
    const float end = k < n ? layers[k].t : t_end;
    if (scene.see_through_volumes) {
      const VolumeSegment v = volumes_along(scene, part, end, &lighting);
      add(v.color, v.transmittance);
      total.samples += v.samples;
    }
    if (k == n) break;
    add(layers[k].color.rgb, 1.0f - std::min(layers[k].color.alpha, 1.0f));
    part.tmin = end;
  }
  return total;
}

}  // namespace

Vec3 through_volumes(const Scene& scene, const DynamicFrame* frame, const Ray& ray, float t_end, const Vec3& behind) {
  if (!scene.see_through) return behind;
  const VolumeSegment seg = see_through_along(scene, frame, ray, t_end);
  return seg.color + seg.transmittance * behind;
}

bool through_volumes(const Scene& scene, const DynamicFrame* frame, const Ray& ray, float t_end, Vec3& radiance,
                     Vec3& beta) {
  const VolumeSegment seg = see_through_along(scene, frame, ray, t_end);
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
