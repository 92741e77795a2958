// The path tracer's loop: intersect, add what is emitted (MIS-weighted after a smooth bounce),
// estimate direct light at smooth surfaces, roulette, scatter.
#include "core/shading/path_tracer.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/base/rng.h"
#include "core/scene/scene_intersect.h"
#include "core/shading/direct_light.h"
#include "core/shading/light_sampling.h"
#include "core/shading/path_material.h"
#include "core/shading/plugin_hit.h"
#include "core/shading/volume_lighting.h"

namespace frameless {
namespace {

// Roulette starts after this many scattering events; survival is at most kMaxSurvival, so even
// paths inside a white furnace end.
constexpr int kRouletteStart = 3;
constexpr float kMaxSurvival = 0.95f;

}  // namespace

Vec3 trace_path(const Scene& scene, const Ray& camera_ray, uint64_t seed, const DynamicFrame* frame,
                const Hit* known_hit, Hit* first_hit, SurfacePoint* first_point, int* bounces,
                const PathOptions& options, Vec3* first_albedo) {
  const bool emits = environment_emits(scene);
  DirectLight st{scene, frame, options.strategy, Rng(seed), emits || !scene.settings.skips.emitters, false,
                 !emits && !scene.settings.skips.emitters};
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
    const bool found = scene_intersect(scene, frame, ray, bounce == 0 ? known_hit : nullptr, hit);
    if (bounce == 0 && first_hit) *first_hit = hit;
    // The volume shader's light on the way, and its shade on what follows.
    if (scene.see_through && !through_volumes(scene, frame, ray, found ? hit.t : kInfinity, radiance, beta)) break;
    // Parker's lights with an extent, reached by a BSDF-sampled ray before any surface.
    if (smooth_bounce && st.extended_lights && st.strategy != LightStrategy::kLightOnly) {
      for (const Light& light : frame_lights(scene, frame)) {
        Vec3 le;
        float pl;
        if (light.has_extent() && parker_light_hit(light, prev, ray.dir, found ? hit.t : kInfinity, le, pl)) {
          // Inside an absorbing dielectric: attenuated over the way to the light.
          const float t = light.kind == LightKind::kDirectional ? kInfinity : glm::length(light.position - prev);
          if (max_component(extinction) > 0.0f) le *= beer(extinction, t);
          radiance += beta * le * bsdf_weight(st.strategy, bsdf_pdf, pl);
        }
      }
    }
    if (!found) {
      if (st.environment) {
        // Escaping inside an absorbing medium: exp(-kappa inf) = 0.
        const Vec3 bg = escaped_radiance(scene.environment.get(), scene.settings.background, ray.dir) *
                        beer(extinction, kInfinity);
        const float w = smooth_bounce ? bsdf_weight(st.strategy, bsdf_pdf, environment_pdf(scene, ray.dir)) : 1.0f;
        radiance += beta * bg * w;
      }
      break;
    }
    SurfacePoint sp = scene_surface_point(scene, frame, ray, hit);
    if (max_component(extinction) > 0.0f) beta *= beer(extinction, glm::length(sp.p - ray.org));
    const MaterialParams m = material_at(scene, frame, ray, hit, sp);
    if (bounce == 0 && first_point) *first_point = sp;
    if (bounce == 0 && first_albedo) *first_albedo = guide_albedo(m);
    if (max_component(m.emission) > 0.0f) {
      float w = 1.0f;  // seen from the camera, a mirror, or an emitter light sampling cannot pick
      const uint32_t index = !smooth_bounce || hit.inst != kInvalidId || is_dynamic_prim(hit.prim) || is_volume_prim(hit.prim)
                                 ? kInvalidId
                                 : scene.emitters.find(hit.prim);
      if (index != kInvalidId)
        w = bsdf_weight(st.strategy, bsdf_pdf, emitter_pdf(scene, index, ray.dir, sp.ng, hit.t));
      radiance += beta * m.emission * w;
    }
    if (bounce >= max_bounces) break;
    PathSurface s = make_path_surface(m, sp, -ray.dir);
    std::optional<PluginBsdf> plugin;  // built only on plug-in surfaces
    if (m.cls == MaterialClass::kShader) {  // a plug-in's BSDF, where it has one
      const ShaderMaterial& sh = scene.shaders[m.shader];
      plugin.emplace(PluginBsdf{sh.shader, sh.params.data(), make_plugin_hit(scene, ray, hit, sp, bounce), path_plugin_host(scene)});
      attach_plugin_bsdf(s, m, *plugin);
    }
    const Vec3 origin = offset_ray_origin(sp.p, sp.ng, sp.scale);
    radiance += beta * direct_light(st, s, origin, extinction);
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
