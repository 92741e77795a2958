// Parker et al. 1999 shading, section 3.1: each material class evaluates only its non-zero terms.
//
// Conventions: e is the unit vector toward the viewer (-ray.dir), n the shading normal turned
// toward e, l the unit vector toward a light, h = normalize(e + l).
//
// The seed's OCR prints the Phong highlight as (h.l)^N in equations 1 and 2. Since
// h.l = h.e for every surface orientation, that term could not depend on the normal and would
// give no highlight at all; it is OCR damage of the Blinn-Phong (h.n)^N, which we use.
// Equation 2 prints the polished highlight as s k_h (h.l)^N without l_e; we multiply by l_e as
// equation 1 does, so coloured and multiple lights act alike on every class (same for white).
//
// Specialisation (docs/adaptive.md): every internal function is a template on the ShadeBits of
// the path (core/scene/scene_analysis.h). trace_sample picks the path once per sample from the scene's
// features and SkipConfig; a cleared bit removes the light loop, the dielectric class and media,
// or the Phong lobes at compile time, so the per-ray code carries no branch for them.
#include "core/shading/shading.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "core/accel/instance.h"
#include "core/scene/instance_texturing.h"
#include "core/scene/scene_analysis.h"
#include "core/scene/scene_intersect.h"
#include "core/shading/volume_lighting.h"
#include "core/scene/texturing.h"
#include "core/shading/plugin_hit.h"
#include "core/shading/soft_shadow.h"

namespace frameless {

namespace {


// Per-sample constants of a shading path (read once per sample, not per ray).
struct ShadeContext {
  const Scene& scene;
  float min_weight;  // pruning threshold: min_contribution, or 0 with SkipConfig::prune off
  bool any_hit;      // shadow rays by any-hit traversal (SkipConfig::any_hit)
  int max_depth;
  uint64_t rng_seed;        // the sample's own stream (area-sampled shadows), drawn lazily
  mutable uint32_t draws;   // streams handed out so far in this sample
  const DynamicFrame* frame;  // moving objects, lights and materials at the sample's instant
  mutable int deepest;        // deepest ray-tree level traced so far (the reflection depth view)
};

ShadeContext make_context(const Scene& scene, uint64_t rng_seed, const DynamicFrame* frame) {
  const RenderSettings& s = scene.settings;
  return ShadeContext{scene, s.skips.prune ? s.min_contribution : 0.0f, s.skips.any_hit,
                      s.max_depth, rng_seed, 0, frame, 0};
}

// Shadow factor of a light with an extent, or with transparent shadows (cold path: kept out of
// line so the hard-shadow loop stays small). Returns s (per channel when dielectrics tint it).
Vec3 extended_visibility(const ShadeContext& c, const Light& light, const Vec3& origin,
                         const Vec3& l, float tmax, float tan_half, float half_angle,
                         uint32_t receiver) {
  const RenderSettings& st = c.scene.settings;
  ShadowQuery q;
  q.org = origin;
  q.dir = l;
  q.tmax = tmax;
  q.tan_half = tan_half;
  q.half_angle = half_angle;
  q.skip_dielectrics = st.transparent_shadows;
  q.receiver = receiver;
  Ray ray;
  ray.org = origin;
  ray.dir = l;
  ray.tmax = tmax;
  const ShadowMode mode = light.has_extent() ? st.shadows : ShadowMode::kHard;
  if (mode == ShadowMode::kHard || !(tan_half > 0.0f)) {
    return shadow_transmittance(c.scene, ray, false, c.frame);  // only reached with transparent shadows
  }
  if (mode == ShadowMode::kBeam) return beam_visibility(c.scene, q, c.frame);
  if (mode == ShadowMode::kSoft) {
    const float s = soft_visibility(c.scene, q, c.frame);
    if (!(s > 0.0f) || !st.transparent_shadows) return Vec3(s);
    return s * shadow_transmittance(c.scene, ray, true, c.frame);
  }
  // One stream per shadow query of the sample: no generator is set up on paths that need none.
  Rng rng(mix64(c.rng_seed + c.draws++));
  return area_visibility(c.scene, q, st.shadow_samples, rng, c.frame);
}

// Calls f(s l_e, l, n.l) for each light that faces the surface and is not fully shadowed.
// Hard shadows: one any-hit ray to the light's centre, ending just short of the light. Lights
// with an extent use the scene's shadow mode (soft_shadow.h).
template <class F>
[[gnu::always_inline]] inline void for_each_visible_light(const ShadeContext& c, const SurfacePoint& sp,
                                                   F&& f) {
  const Scene& scene = c.scene;
  const Vec3 origin = offset_ray_origin(sp.p, sp.ng, sp.scale);
  const bool transparent = scene.settings.transparent_shadows;
  const bool extended_mode = scene.settings.shadows != ShadowMode::kHard;
  for (const Light& light : frame_lights(scene, c.frame)) {
    Vec3 l;
    float tmax, tan_half = 0.0f, half_angle = 0.0f;
    if (light.kind == LightKind::kDirectional) {
      l = -light.direction;
      tmax = kInfinity;
      if (extended_mode) {
        half_angle = light.angular_radius;
        tan_half = std::tan(half_angle);
      }
    } else {
      const Vec3 to_light = light.position - origin;
      const float dist = glm::length(to_light);
      if (!(dist > 0.0f)) continue;
      l = to_light / dist;
      // Stop short of the light: its centre, or the surface of a spherical light.
      tmax = std::max(0.0f, dist - light.radius) * (1.0f - 0x1.0p-12f);
      // The cone the light subtends, only where soft or area shadows will use it.
      if (extended_mode && light.radius > 0.0f && dist > light.radius) {
        half_angle = std::asin(light.radius / dist);
        tan_half = light.radius / std::sqrt((dist - light.radius) * (dist + light.radius));
      }
    }
    const float nl = glm::dot(sp.ns, l);
    // A light behind the shading or the geometric surface cannot light it (s = 0).
    if (nl <= 0.0f || glm::dot(sp.ng, l) <= 0.0f) continue;
    if (!(tmax > 0.0f)) {
      f(light.color, l, nl);
      continue;
    }
    Ray shadow;
    shadow.org = origin;
    shadow.dir = l;
    shadow.tmin = 0.0f;
    shadow.tmax = tmax;
    if (transparent || (extended_mode && light.has_extent())) {
      Vec3 s = extended_visibility(c, light, origin, l, tmax, tan_half, half_angle, sp.prim);
      // Area and transparent shadow rays meet isosurfaces; Parker's cone query does not: there
      // they are sampled across the light's cone. The volume shader's volumes dim either way.
      if (!scene.volumes.empty() && max_component(s) > 0.0f) {
        const bool cone = light.has_extent() && scene.settings.shadows == ShadowMode::kSoft && tan_half > 0.0f;
        s *= cone ? volume_cone_shadow(scene, shadow, tan_half) : volume_shadow(scene, shadow, false);
      }
      if (max_component(s) > 0.0f) f(light.color * s, l, nl);
      continue;
    }
    if (c.any_hit) {
      if (scene_occluded(scene, c.frame, shadow)) continue;
    } else {
      Hit blocker;  // ablation: closest-hit traversal for the same visibility question
      if (scene_intersect(scene, c.frame, shadow, blocker)) continue;
    }
    if (scene.see_through_volumes) {  // transparent shadows of the volume shader's volumes
      const Vec3 t = volume_shadow(scene, shadow, false);
      if (max_component(t) > 0.0f) f(light.color * t, l, nl);
      continue;
    }
    f(light.color, l, nl);
  }
}

template <uint32_t F>
Vec3 trace_from(const ShadeContext& c, const Ray& ray, const Vec3& start, int depth,
                const Vec3& weight, const MaterialParams* medium, Hit* first_hit,
                SurfacePoint* first_point, const Hit* known_hit);

// Traces a secondary ray when the depth limit and the pruning threshold allow it.
// `start` is the surface point before the origin offset (for the distance travelled inside).
template <uint32_t F>
inline Vec3 trace_child(const ShadeContext& c, const Vec3& start, const Vec3& origin,
                        const Vec3& dir, int depth, const Vec3& child_weight,
                        const MaterialParams* medium) {
  if (depth >= c.max_depth) return Vec3(0.0f);
  // Zero-weight branches are always pruned, so a threshold of 0 cannot explode the tree.
  const float w = max_component(child_weight);
  if (w <= 0.0f || w < c.min_weight) return Vec3(0.0f);
  Ray r;
  r.org = origin;
  r.dir = glm::normalize(dir);
  r.tmin = 0.0f;
  return trace_from<F>(c, r, start, depth + 1, child_weight, medium, nullptr, nullptr, nullptr);
}

// The mirror direction at a surface point (core/shading/optics.h).
inline Vec3 mirror(const Vec3& d, const SurfacePoint& sp) { return mirror_direction(d, sp.ns, sp.ng); }

template <uint32_t F>
Vec3 shade_diffuse(const ShadeContext& c, const MaterialParams& m, const SurfacePoint& sp) {
  // Equation 1 with k_h = k_s = k_t = 0: k_d (l_a + s l_e n.l).
  Vec3 light_sum = ambient_light(c.scene.ambient, sp.p, sp.ns);
  if constexpr ((F & kShadeLights) != 0)
    for_each_visible_light(c, sp, [&](const Vec3& le, const Vec3&, float nl) { light_sum += le * nl; });
  return m.kd * light_sum;
}

template <uint32_t F>
Vec3 shade_metal(const ShadeContext& c, const Ray& ray, const MaterialParams& m, const SurfacePoint& sp,
                 int depth, const Vec3& weight, const MaterialParams* medium) {
  // Equation 1 with k_d = k_t = 0 and k_h = k_s: s l_e k_s (h.n)^N + k_s L_s.
  const Vec3 e = -ray.dir;
  Vec3 out(0.0f);
  if constexpr ((F & kShadeLights) != 0 && (F & kShadeHighlights) != 0)
    for_each_visible_light(c, sp, [&](const Vec3& le, const Vec3& l, float) {
      out += le * m.ks * phong_lobe(sp.ns, e, l, m.phong_exponent);
    });
  out += m.ks * trace_child<F>(c, sp.p, offset_ray_origin(sp.p, sp.ng, sp.scale),
                               mirror(ray.dir, sp), depth, weight * m.ks, medium);
  return out;
}

template <uint32_t F>
Vec3 shade_dielectric(const ShadeContext& c, const Ray& ray, const MaterialParams& m,
                      const SurfacePoint& sp, int depth, const Vec3& weight,
                      const MaterialParams* medium) {
  // Equation 1 with k_d = 0, k_s from Schlick, k_t = 1 - k_s, plus a Phong term.
  const Vec3 e = -ray.dir;
  const float cos_i = std::clamp(glm::dot(e, sp.ns), 0.0f, 1.0f);
  // Entering through the outward side goes from air (1) into the material (ior).
  const float eta = sp.front_face ? 1.0f / m.ior : m.ior;
  const FresnelTerms f = dielectric_fresnel(cos_i, eta, r0_from_ior(m.ior));
  Vec3 out(0.0f);
  if constexpr ((F & kShadeLights) != 0 && (F & kShadeHighlights) != 0)
    if (max_component(m.kh) > 0.0f)
      for_each_visible_light(c, sp, [&](const Vec3& le, const Vec3& l, float) {
        out += le * m.kh * phong_lobe(sp.ns, e, l, m.phong_exponent);
      });
  // Reflection stays on the incident side, in the incident medium.
  out += f.ks * trace_child<F>(c, sp.p, offset_ray_origin(sp.p, sp.ng, sp.scale),
                               mirror(ray.dir, sp), depth, weight * f.ks, medium);
  if (!f.total_internal_reflection) {
    const Vec3 t = eta * ray.dir + (eta * cos_i - f.cos_t) * sp.ns;
    // Leaving returns to air: nested dielectrics are not tracked (one medium at a time).
    const MaterialParams* next = sp.front_face ? &m : nullptr;
    out += f.kt * trace_child<F>(c, sp.p, offset_ray_origin(sp.p, -sp.ng, sp.scale), t, depth,
                                 weight * f.kt, next);
  }
  return out;
}

template <uint32_t F>
Vec3 shade_polished(const ShadeContext& c, const Ray& ray, const MaterialParams& m,
                    const SurfacePoint& sp, int depth, const Vec3& weight,
                    const MaterialParams* medium) {
  // Equation 2 (coupled model): k_d l_a (1 - k_s(e,n)) + s k_d l_e (1 - (1 - n.e)^5)(1 - (1 -
  // n.l)^5)
  //                            + s k_h l_e (h.n)^N + k_s(e,n) L_s.
  const Vec3 e = -ray.dir;
  const float en = std::clamp(glm::dot(e, sp.ns), 0.0f, 1.0f);
  const Vec3 ks = schlick(en, m.r0);
  Vec3 out = m.kd * ambient_light(c.scene.ambient, sp.p, sp.ns) * (Vec3(1.0f) - ks);
  if constexpr ((F & kShadeLights) != 0) {
    const float view_factor = 1.0f - pow5(1.0f - en);
    const bool highlight = (F & kShadeHighlights) != 0 && max_component(m.kh) > 0.0f;
    for_each_visible_light(c, sp, [&](const Vec3& le, const Vec3& l, float nl) {
      out += m.kd * le * (view_factor * (1.0f - pow5(1.0f - nl)));
      if (highlight) out += le * m.kh * phong_lobe(sp.ns, e, l, m.phong_exponent);
    });
  }
  out += ks * trace_child<F>(c, sp.p, offset_ray_origin(sp.p, sp.ng, sp.scale),
                             mirror(ray.dir, sp), depth, weight * ks, medium);
  return out;
}

// A plug-in shader's host (include/frameless/shader.h): its calls come back into this sample.
template <uint32_t F>
struct PluginHost {
  const ShadeContext& c;
  const SurfacePoint& sp;
  int depth;
  Vec3 weight;
  const MaterialParams* medium;
  Rng rng{0};
  bool seeded = false;
  static PluginHost& of(void* ctx) { return *static_cast<PluginHost*>(ctx); }
  static void lights(void* ctx, fl_light_visitor visit, void* user) {
    if constexpr ((F & kShadeLights) != 0)
      for_each_visible_light(of(ctx).c, of(ctx).sp, [&](const Vec3& le, const Vec3& l, float nl) { visit(user, to_fl(le), to_fl(l), nl); });
  }
  static fl_vec3 ambient(void* ctx, fl_vec3 n) {
    const Vec3 d = from_fl(n);
    const float len = glm::length(d);
    return to_fl(len > 0.0f && std::isfinite(len) ? ambient_light(of(ctx).c.scene.ambient, of(ctx).sp.p, d / len) : Vec3(0.0f));
  }
  static fl_vec3 trace(void* ctx, fl_vec3 direction, fl_vec3 weight) {
    PluginHost& h = of(ctx);
    const Vec3 d = from_fl(direction), w = glm::max(from_fl(weight), Vec3(0.0f));
    if (!(glm::dot(d, d) > 0.0f) || !is_finite(d) || !is_finite(w)) return to_fl(Vec3(0.0f));
    const bool above = glm::dot(d, h.sp.ng) > 0.0f;  // leaves on the side it points to
    const Vec3 origin = offset_ray_origin(h.sp.p, above ? h.sp.ng : -h.sp.ng, h.sp.scale);
    return to_fl(trace_child<F>(h.c, h.sp.p, origin, d, h.depth, h.weight * w, above ? h.medium : nullptr));
  }
  static float random(void* ctx) {
    PluginHost& h = of(ctx);
    if (!h.seeded) h.rng = Rng(mix64(h.c.rng_seed + h.c.draws++)), h.seeded = true;
    return h.rng.next_float();
  }
  static fl_vec4 texture(void* ctx, float slot, float u, float v, fl_vec3 p) {
    return plugin_texture(of(ctx).c.scene, slot, u, v, p);
  }
};

template <uint32_t F>
Vec3 shade_plugin(const ShadeContext& c, const Ray& ray, const Hit& hit, const MaterialParams& m, const SurfacePoint& sp,
                  int depth, const Vec3& weight, const MaterialParams* medium) {
  const ShaderMaterial& s = c.scene.shaders[m.shader];
  PluginHost<F> ph{c, sp, depth, weight, medium};
  const fl_host host{FRAMELESS_SHADER_API_VERSION, &ph, &PluginHost<F>::lights, &PluginHost<F>::ambient,
                     &PluginHost<F>::trace, &PluginHost<F>::random, &plugin_noise, &plugin_turbulence,
                     &PluginHost<F>::texture};
  const fl_hit h = make_plugin_hit(c.scene, ray, hit, sp, depth);
  Vec3 r = from_fl(s.shader->shade(&host, &h, s.params.data()));
  for (int k = 0; k < 3; ++k) r[k] = std::isfinite(r[k]) && r[k] > 0.0f ? r[k] : 0.0f;  // no NaN or negative light
  return r;
}

template <uint32_t F>
Vec3 shade_material(const ShadeContext& c, const Ray& ray, const Hit& hit, const MaterialParams& m,
                    const SurfacePoint& sp, int depth, const Vec3& weight,
                    const MaterialParams* medium) {
  switch (m.cls) {
    case MaterialClass::kDiffuse:
      return shade_diffuse<F>(c, m, sp);
    case MaterialClass::kMetal:
      return shade_metal<F>(c, ray, m, sp, depth, weight, medium);
    case MaterialClass::kDielectric:
      // Without the refraction bit the scene has no dielectric: this case cannot occur.
      if constexpr ((F & kShadeRefraction) != 0)
        return shade_dielectric<F>(c, ray, m, sp, depth, weight, medium);
      else
        return Vec3(0.0f);
    case MaterialClass::kPolished:
      return shade_polished<F>(c, ray, m, sp, depth, weight, medium);
    case MaterialClass::kShader:
      return shade_plugin<F>(c, ray, hit, m, sp, depth, weight, medium);
  }
  return Vec3(0.0f);
}

// Adds what the surface emits; scenes without emitters skip even the add (and keep their bits).
inline Vec3 emitted(const ShadeContext& c, const MaterialParams& m, const Vec3& reflected) {
  return c.scene.features.has_emission ? reflected + m.emission : reflected;
}

template <uint32_t F>
Vec3 shade_surface_path(const ShadeContext& c, const Ray& ray, const Hit& hit,
                        const SurfacePoint& sp, int depth, const Vec3& weight,
                        const MaterialParams* medium) {
  const MaterialParams& base = frame_material(c.scene, c.frame, sp.material);
  // Untextured materials are shaded in place: no texture coordinate is ever computed for them.
  // Dynamic objects have no texture coordinates either (their frame moves per sample).
  if (!base.textured() || is_dynamic_prim(hit.prim) || is_volume_prim(hit.prim))
    return emitted(c, base, shade_material<F>(c, ray, hit, base, sp, depth, weight, medium));
  MaterialParams m = base;
  SurfacePoint tsp = sp;
  if (hit.inst != kInvalidId)
    apply_instance_textures(c.scene, *c.scene.accel.top_in_use(frame_instances(c.frame)), ray, hit, m, tsp);
  else
    apply_textures(c.scene, ray, hit, m, tsp);
  return emitted(c, m, shade_material<F>(c, ray, hit, m, tsp, depth, weight, medium));
}

template <uint32_t F>
Vec3 trace_from(const ShadeContext& c, const Ray& ray, const Vec3& start, int depth,
                const Vec3& weight, const MaterialParams* medium, Hit* first_hit,
                SurfacePoint* first_point, const Hit* known_hit) {
  const Scene& scene = c.scene;
  if (depth > c.deepest) c.deepest = depth;
  Hit hit;
  bool found;
  if (known_hit) {  // a packet already traced the static scene: add what moves
    hit = *known_hit;
    found = merge_nonstatic_hits(scene, c.frame, ray, hit);
  } else {
    found = scene_intersect(scene, c.frame, ray, hit);
  }
  if (first_hit) *first_hit = hit;
  // Volume-shader and MIP volumes between the origin and what the ray meets (a no-op without).
  const auto seen = [&](const Vec3& behind) { return through_volumes(scene, c.frame, ray, found ? hit.t : kInfinity, behind); };
  if (!found) {
    Vec3 bg = escaped_radiance(scene.environment.get(), scene.settings.background, ray.dir);
    // An escaping ray inside an absorbing medium travels forever: exp(-kappa inf) = 0.
    if constexpr ((F & kShadeAbsorption) != 0)
      if (medium)
        for (int k = 0; k < 3; ++k)
          if (medium->extinction[k] > 0.0f) bg[k] = 0.0f;
    return seen(bg);
  }
  const SurfacePoint sp = scene_surface_point(scene, c.frame, ray, hit);
  if (first_point) *first_point = sp;
  if constexpr ((F & kShadeAbsorption) == 0) {
    // No absorbing medium in the scene: light is never attenuated between surfaces.
    return seen(shade_surface_path<F>(c, ray, hit, sp, depth, weight, medium));
  } else {
    if (!medium || max_component(medium->extinction) <= 0.0f)
      return seen(shade_surface_path<F>(c, ray, hit, sp, depth, weight, medium));
    // Light travelling inside a dielectric decays as exp(-kappa t), t the distance between the
    // two surface points (not hit.t, which starts at the offset origin).
    const float t = glm::length(sp.p - start);
    const Vec3 attenuation(std::exp(-medium->extinction.x * t),
                           std::exp(-medium->extinction.y * t),
                           std::exp(-medium->extinction.z * t));
    const Vec3 w = weight * attenuation;
    // Prune a branch the medium has already dimmed below the threshold.
    const float wmax = max_component(w);
    if (wmax <= 0.0f || wmax < c.min_weight) return Vec3(0.0f);
    return seen(attenuation * shade_surface_path<F>(c, ray, hit, sp, depth, w, medium));
  }
}

// One entry per shading path, indexed by its ShadeBits.
using TraceFn = Vec3 (*)(const ShadeContext&, const Ray&, const Vec3&, int, const Vec3&,
                         const MaterialParams*, Hit*, SurfacePoint*, const Hit*);
template <size_t... I>
constexpr std::array<TraceFn, sizeof...(I)> trace_table(std::index_sequence<I...>) {
  return {&trace_from<uint32_t(I)>...};
}
constexpr auto kTracePaths = trace_table(std::make_index_sequence<kShadePaths>{});

}  // namespace

Vec3 hemisphere_ambient(const Vec3& a, const Vec3& b, const Vec3& axis, const Vec3& n) {
  const float cos_theta = glm::dot(n, axis);
  // sin from the cross product stays accurate near 0 and pi, where sqrt(1 - cos^2) does not.
  const float half_sin = 0.5f * std::min(1.0f, glm::length(glm::cross(n, axis)));
  // Seed 3.1.1, piecewise: theta < pi/2 (cos > 0) sees mostly A, otherwise mostly B.
  if (cos_theta > 0.0f) return (1.0f - half_sin) * a + half_sin * b;
  return half_sin * a + (1.0f - half_sin) * b;
}

Vec3 ambient_light(const Ambient& ambient, const Vec3& p, const Vec3& n) {
  switch (ambient.kind) {
    case AmbientKind::kNone:
      return Vec3(0.0f);
    case AmbientKind::kConstant:
      return ambient.constant;
    case AmbientKind::kHemisphere:
      return hemisphere_ambient(ambient.a, ambient.b, ambient.axis, n);
    case AmbientKind::kIrradianceVolume:
      return ambient.volume ? ambient.volume->irradiance(p, n) * (1.0f / kPi) : Vec3(0.0f);
  }
  return Vec3(0.0f);
}

Vec3 trace_radiance(const Scene& scene, const Ray& ray, int depth, const Vec3& weight,
                    const MaterialParams* medium, Hit* first_hit, SurfacePoint* first_point) {
  // A medium handed in from outside needs the refraction and absorption code.
  const uint32_t path =
      shade_path(scene) | (medium ? kShadeRefraction | kShadeAbsorption : 0u);
  return trace_radiance_path(scene, path, ray, depth, weight, medium, first_hit, first_point);
}

Vec3 trace_radiance_path(const Scene& scene, uint32_t path, const Ray& ray, int depth,
                         const Vec3& weight, const MaterialParams* medium, Hit* first_hit,
                         SurfacePoint* first_point, uint64_t rng_seed,
                         const DynamicFrame* frame, const Hit* known_hit, int* levels) {
  const ShadeContext c = make_context(scene, rng_seed, frame);
  const Vec3 l = kTracePaths[path % kShadePaths](c, ray, ray.org, depth, weight, medium, first_hit,
                                                 first_point, known_hit);
  if (levels) *levels = c.deepest - depth;
  return l;
}

}  // namespace frameless
