// Next-event estimation at one vertex, shared by the path tracer and instant global
// illumination: each Parker light, one emissive triangle, one environment direction.
#include "core/shading/direct_light.h"

#include <algorithm>
#include <cmath>

#include "core/scene/instance_texturing.h"
#include "core/scene/scene_intersect.h"
#include "core/scene/texturing.h"
#include "core/shading/light_sampling.h"
#include "core/shading/volume_lighting.h"

namespace frameless {

MaterialParams material_at(const Scene& scene, const DynamicFrame* frame, const Ray& ray,
                           const Hit& hit, SurfacePoint& sp) {
  MaterialParams m = frame_material(scene, frame, sp.material);
  if (!m.textured() || is_dynamic_prim(hit.prim) || is_volume_prim(hit.prim)) return m;
  if (hit.inst != kInvalidId)
    apply_instance_textures(scene, *scene.accel.top_in_use(frame_instances(frame)), ray, hit, m, sp);
  else
    apply_textures(scene, ray, hit, m, sp);
  return m;
}

namespace {

// The share of a light sample's light that reaches origin, per channel: 0 when something blocks
// it, else what the volume shader's volumes let through (1 without them).
Vec3 visible(const DirectLight& st, const Vec3& origin, const LightSample& ls) {
  Ray r;
  r.org = origin;
  r.dir = ls.wi;
  r.tmin = 0.0f;
  r.tmax = ls.tmax;
  if (scene_occluded(st.scene, st.frame, r)) return Vec3(0.0f);
  return st.scene.see_through_volumes ? volume_shadow(st.scene, r, false) : Vec3(1.0f);
}

}  // namespace

Vec3 direct_light(DirectLight& st, const PathSurface& s, const Vec3& origin, const Vec3& extinction) {
  const bool absorbing = max_component(extinction) > 0.0f;
  const bool smooth = path_is_smooth(s);
  const bool lobes = path_has_light_lobes(s);
  Vec3 sum(0.0f);
  const auto cos_at = [&](const Vec3& wi) { return std::max(0.0f, glm::dot(s.frame.n, wi)); };
  for (const Light& light : frame_lights(st.scene, st.frame)) {
    LightSample ls;
    const float u1 = st.rng.next_float(), u2 = st.rng.next_float();
    if (!sample_parker_light(light, origin, u1, u2, ls)) continue;
    const float c = cos_at(ls.wi);
    if (c <= 0.0f) continue;
    const Vec3 fs = smooth ? path_eval(s, ls.wi) : Vec3(0.0f);
    const Vec3 fl = lobes ? path_eval_light_lobes(s, ls.wi) : Vec3(0.0f);
    Vec3 contrib;
    if (ls.pdf == 0.0f) {  // a delta light: only light sampling can find it
      contrib = (fs + fl) * ls.radiance * c;
    } else {  // the lobes are never BSDF-sampled, so their light-sampled estimate counts fully
      const float w = light_weight(st.strategy, ls.pdf, path_pdf(s, ls.wi));
      contrib = (fs * w + fl) * ls.radiance * (c / ls.pdf);
    }
    if (absorbing) contrib *= beer(extinction, ls.tmax);
    if (max_component(contrib) > 0.0f) sum += contrib * visible(st, origin, ls);
  }
  if (!smooth || st.strategy == LightStrategy::kBsdfOnly) return sum;
  if (!st.scene.emitters.empty()) {
    LightSample ls;
    const float u0 = st.rng.next_float(), u1 = st.rng.next_float(), u2 = st.rng.next_float();
    if (sample_emitter(st.scene, st.frame, origin, u0, u1, u2, ls)) {
      const float c = cos_at(ls.wi);
      const Vec3 f = path_eval(s, ls.wi);
      if (c > 0.0f && max_component(f) > 0.0f) {
        const float w = light_weight(st.strategy, ls.pdf, path_pdf(s, ls.wi));
        const Vec3 t = absorbing ? beer(extinction, ls.tmax) : Vec3(1.0f);
        sum += t * f * ls.radiance * (w * c / ls.pdf) * visible(st, origin, ls);
      }
    }
  }
  if (st.environment) {
    Rng copy = st.rng;
    Rng& rng = st.black_environment ? copy : st.rng;
    const float u1 = rng.next_float(), u2 = rng.next_float();
    LightSample ls;
    if (!sample_environment(st.scene, u1, u2, ls)) return sum;
    const float c = cos_at(ls.wi);
    const Vec3 f = c > 0.0f ? path_eval(s, ls.wi) : Vec3(0.0f);
    if (max_component(f) > 0.0f) {
      const float w = light_weight(st.strategy, ls.pdf, path_pdf(s, ls.wi));
      const Vec3 t = absorbing ? beer(extinction, kInfinity) : Vec3(1.0f);
      sum += t * f * ls.radiance * (w * c / ls.pdf) * visible(st, origin, ls);
    }
  }
  return sum;
}


}  // namespace frameless
