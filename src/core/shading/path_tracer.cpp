// The path tracer's loop: intersect, add what is emitted (MIS-weighted after a smooth bounce),
// estimate direct light at smooth surfaces, roulette, scatter.
#include "core/shading/path_tracer.h"

#include <algorithm>
#include <cmath>

#include "core/base/rng.h"
#include "core/scene/instance_texturing.h"
#include "core/scene/scene_intersect.h"
#include "core/scene/texturing.h"
#include "core/shading/light_sampling.h"
#include "core/shading/path_material.h"

namespace frameless {
namespace {

// Roulette starts after this many scattering events; survival is at most kMaxSurvival, so even
// paths inside a white furnace end.
constexpr int kRouletteStart = 3;
constexpr float kMaxSurvival = 0.95f;

// Power heuristic (Veach 1997, beta = 2): the weight of the strategy with density a.
inline float power_weight(float a, float b) {
  const float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// Weight of a light-sampled estimate (density pl) against BSDF sampling (density pb).
inline float light_weight(LightStrategy s, float pl, float pb) {
  return s == LightStrategy::kMis ? power_weight(pl, pb) : s == LightStrategy::kLightOnly ? 1.0f : 0.0f;
}
// Weight of a BSDF-sampled hit of a light that light sampling also finds.
inline float bsdf_weight(LightStrategy s, float pb, float pl) {
  return s == LightStrategy::kMis ? power_weight(pb, pl) : s == LightStrategy::kBsdfOnly ? 1.0f : 0.0f;
}

// The material at a hit, textured (instances in object space; moving objects carry none).
MaterialParams material_at(const Scene& scene, const DynamicFrame* frame, const Ray& ray,
                           const Hit& hit, SurfacePoint& sp) {
  MaterialParams m = frame_material(scene, frame, sp.material);
  if (!m.textured() || is_dynamic_prim(hit.prim)) return m;
  if (hit.inst != kInvalidId)
    apply_instance_textures(scene, *scene.accel.top_in_use(frame_instances(frame)), ray, hit, m, sp);
  else
    apply_textures(scene, ray, hit, m, sp);
  return m;
}

inline Vec3 beer(const Vec3& extinction, float t) {
  return Vec3(std::exp(-extinction.x * t), std::exp(-extinction.y * t), std::exp(-extinction.z * t));
}

struct PathState {
  const Scene& scene;
  const DynamicFrame* frame;
  LightStrategy strategy;
  Rng rng;
  bool environment;    // the background emits: sample it
  bool extended_lights;  // some Parker light has an extent (BSDF rays may reach it)
};

bool occluded(const PathState& st, const Vec3& origin, const LightSample& ls) {
  Ray r;
  r.org = origin;
  r.dir = ls.wi;
  r.tmin = 0.0f;
  r.tmax = ls.tmax;
  return scene_occluded(st.scene, st.frame, r);
}

// Direct light at a surface: Parker's lights (through the smooth part and the highlight lobes),
// one emissive triangle and one environment direction (through the smooth part).
Vec3 direct_light(PathState& st, const PathSurface& s, const Vec3& origin) {
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
    if (max_component(contrib) > 0.0f && !occluded(st, origin, ls)) sum += contrib;
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
        if (!occluded(st, origin, ls)) sum += f * ls.radiance * (w * c / ls.pdf);
      }
    }
  }
  if (st.environment) {
    const float u1 = st.rng.next_float(), u2 = st.rng.next_float();
    const LightSample ls = sample_environment(st.scene, u1, u2);
    const float c = cos_at(ls.wi);
    const Vec3 f = c > 0.0f ? path_eval(s, ls.wi) : Vec3(0.0f);
    if (max_component(f) > 0.0f) {
      const float w = light_weight(st.strategy, ls.pdf, path_pdf(s, ls.wi));
      if (!occluded(st, origin, ls)) sum += f * ls.radiance * (w * c / ls.pdf);
    }
  }
  return sum;
}

}  // namespace

Vec3 trace_path(const Scene& scene, const Ray& camera_ray, uint64_t seed, const DynamicFrame* frame,
                const Hit* known_hit, Hit* first_hit, SurfacePoint* first_point, int* bounces,
                const PathOptions& options) {
  PathState st{scene, frame, options.strategy, Rng(seed),
               max_component(scene.settings.background) > 0.0f, false};
  for (const Light& l : frame_lights(scene, frame)) st.extended_lights |= l.has_extent();
  const int max_bounces = options.max_bounces >= 0 ? options.max_bounces : scene.settings.max_depth;

  Vec3 radiance(0.0f), beta(1.0f);
  Ray ray = camera_ray;
  bool smooth_bounce = false;  // the last scattering was BSDF-sampled by a density (MIS applies)
  float bsdf_pdf = 0.0f;       // its density
  Vec3 prev(0.0f);             // the last scattering point
  Vec3 extinction(0.0f);       // of the dielectric the path is inside (Beer's law)
  int bounce = 0;
  for (;; ++bounce) {
    Hit hit;
    bool found;
    if (bounce == 0 && known_hit) {
      hit = *known_hit;
      found = merge_dynamic_hit(frame, ray, hit);
    } else {
      found = scene_intersect(scene, frame, ray, hit);
    }
    if (bounce == 0 && first_hit) *first_hit = hit;
    // Parker's lights with an extent, reached by a BSDF-sampled ray before any surface.
    if (smooth_bounce && st.extended_lights && st.strategy != LightStrategy::kLightOnly) {
      for (const Light& light : frame_lights(scene, frame)) {
        Vec3 le;
        float pl;
        if (light.has_extent() && parker_light_hit(light, prev, ray.dir, found ? hit.t : kInfinity, le, pl))
          radiance += beta * le * bsdf_weight(st.strategy, bsdf_pdf, pl);
      }
    }
    if (!found) {
      if (st.environment) {
        Vec3 bg = scene.settings.background;
        for (int k = 0; k < 3; ++k)  // escaping inside an absorbing medium: exp(-kappa inf)
          if (extinction[k] > 0.0f) bg[k] = 0.0f;
        const float w = smooth_bounce ? bsdf_weight(st.strategy, bsdf_pdf, kEnvironmentPdf) : 1.0f;
        radiance += beta * bg * w;
      }
      break;
    }
    SurfacePoint sp = scene_surface_point(scene, frame, ray, hit);
    if (max_component(extinction) > 0.0f) beta *= beer(extinction, glm::length(sp.p - ray.org));
    const MaterialParams m = material_at(scene, frame, ray, hit, sp);
    if (bounce == 0 && first_point) *first_point = sp;
    if (max_component(m.emission) > 0.0f) {
      float w = 1.0f;  // seen from the camera, a mirror, or an emitter light sampling cannot pick
      const uint32_t index = !smooth_bounce || hit.inst != kInvalidId || is_dynamic_prim(hit.prim)
                                 ? kInvalidId
                                 : scene.emitters.find(hit.prim);
      if (index != kInvalidId)
        w = bsdf_weight(st.strategy, bsdf_pdf, emitter_pdf(scene, index, ray.dir, sp.ng, hit.t));
      radiance += beta * m.emission * w;
    }
    if (bounce >= max_bounces) break;
    const PathSurface s = make_path_surface(m, sp, -ray.dir);
    const Vec3 origin = offset_ray_origin(sp.p, sp.ng, sp.scale);
    radiance += beta * direct_light(st, s, origin);
    if (bounce >= kRouletteStart) {
      const float q = std::min(kMaxSurvival, max_component(beta));
      if (!(st.rng.next_float() < q)) break;
      beta /= q;
    }
    PathScatter sc;
    const float u0 = st.rng.next_float(), u1 = st.rng.next_float(), u2 = st.rng.next_float();
    if (!path_sample(s, u0, u1, u2, sc)) break;
    beta *= sc.weight;
    if (sc.transmitted) extinction = s.front_face ? m.extinction : Vec3(0.0f);
    smooth_bounce = !sc.delta;
    bsdf_pdf = sc.pdf;
    prev = origin;
    ray.org = sc.transmitted ? offset_ray_origin(sp.p, -sp.ng, sp.scale) : origin;
    ray.dir = sc.wi;
    ray.tmin = 0.0f;
    ray.tmax = kInfinity;
  }
  if (bounces) *bounces = bounce;
  return radiance;
}

}  // namespace frameless
