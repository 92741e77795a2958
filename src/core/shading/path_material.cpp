// The physical readings of Parker's classes (path_material.h), on top of the scattering
// functions of bsdf.h and the optics of optics.h.
#include "core/shading/path_material.h"

#include <algorithm>
#include <cmath>

#include "core/shading/bsdf.h"
#include "core/shading/optics.h"

namespace frameless {
namespace {

inline float mean3(const Vec3& v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }

// Mirror of -wo about the shading normal; the geometric normal's when the shading normal would
// send it below the surface (as the Whitted integrator does).
Vec3 mirror_world(const PathSurface& s) { return glm::normalize(mirror_direction(-s.wo_world, s.frame.n, s.ng)); }

inline float cos_out(const PathSurface& s) { return std::clamp(s.wo.z, 0.0f, 1.0f); }

// Probability that polished picks its coat's mirror: the coat's mean Schlick reflectance.
inline float coat_probability(const PathSurface& s) {
  return std::clamp(mean3(schlick(cos_out(s), s.m.r0)), 0.0f, 1.0f);
}

}  // namespace

PathSurface make_path_surface(const MaterialParams& m, const SurfacePoint& sp, const Vec3& wo_world) {
  PathSurface s;
  s.m = m;
  // Plug-in shaders without a BSDF: light transport reads them as diffuse with their albedo (kd).
  if (s.m.cls == MaterialClass::kShader) s.m.cls = MaterialClass::kDiffuse;
  // An interpolated normal can face away from the viewer at silhouettes: shade with the
  // geometric normal there rather than lose the vertex (Whitted clamps the same way).
  s.frame = make_shading_frame(glm::dot(sp.ns, wo_world) > 0.0f ? sp.ns : sp.ng);
  s.wo_world = wo_world;
  s.wo = s.frame.to_local(wo_world);
  s.ng = sp.ng;
  s.front_face = sp.front_face;
  return s;
}

void attach_plugin_bsdf(PathSurface& s, const MaterialParams& m, const PluginBsdf& bsdf) {
  if (m.cls != MaterialClass::kShader || !bsdf.shader || !bsdf.shader->eval || !bsdf.shader->sample) return;
  s.m.cls = MaterialClass::kShader;
  s.plugin = &bsdf;
}

namespace {

// The plug-in's f and density toward wi (both 0 when it returns anything non-finite or negative).
Vec3 plugin_eval(const PathSurface& s, const Vec3& wi, float& pdf) {
  pdf = 0.0f;
  float p = 0.0f;
  const PluginBsdf& b = *s.plugin;
  const fl_vec3 f = b.shader->eval(&b.host, &b.hit, b.params,
                                   fl_vec3{s.wo_world.x, s.wo_world.y, s.wo_world.z}, fl_vec3{wi.x, wi.y, wi.z}, &p);
  const Vec3 r(f.x, f.y, f.z);
  if (!is_finite(r) || r.x < 0.0f || r.y < 0.0f || r.z < 0.0f || !std::isfinite(p) || p < 0.0f) return Vec3(0.0f);
  pdf = p;
  return r;
}

}  // namespace

Vec3 guide_albedo(const MaterialParams& m) {
  if (max_component(m.emission) > 0.0f) return Vec3(0.0f);  // emitters: not the denoiser's
  const Vec3 a = m.cls == MaterialClass::kMetal ? m.ks : m.cls == MaterialClass::kDielectric ? Vec3(1.0f) : m.kd;
  return glm::clamp(a, Vec3(0.0f), Vec3(1.0f));
}

// A glTF metal: GGX of its roughness instead of a mirror (sampled, so it is smooth).
inline bool ggx_metal(const MaterialParams& m) { return m.cls == MaterialClass::kMetal && m.roughness >= 0.0f; }
inline float ggx_alpha(const MaterialParams& m) { return m.roughness * m.roughness; }
// A glTF non-metal: the GGX coat of its roughness over the coupled diffuse base.
inline bool ggx_coated(const MaterialParams& m) {
  return (m.cls == MaterialClass::kPolished || m.cls == MaterialClass::kDiffuse) && m.roughness >= 0.0f;
}

bool path_is_smooth(const PathSurface& s) {
  return s.m.cls == MaterialClass::kDiffuse || s.m.cls == MaterialClass::kShader || s.m.cls == MaterialClass::kPolished || ggx_metal(s.m);
}

bool path_has_light_lobes(const PathSurface& s) {
  // GGX sees Parker's lights through next-event estimation (its lobe is in path_eval).
  if (ggx_metal(s.m) || ggx_coated(s.m) || s.m.cls == MaterialClass::kShader) return false;
  return s.m.cls == MaterialClass::kMetal ? max_component(s.m.ks) > 0.0f
         : s.m.cls == MaterialClass::kDiffuse ? false
                                              : max_component(s.m.kh) > 0.0f;
}

Vec3 path_eval(const PathSurface& s, const Vec3& wi) {
  if (glm::dot(wi, s.ng) <= 0.0f) return Vec3(0.0f);
  float unused;
  if (s.m.cls == MaterialClass::kShader) return plugin_eval(s, wi, unused);
  const Vec3 l = s.frame.to_local(wi);
  if (ggx_coated(s.m)) return ggx_coated_eval(s.m.kd, s.m.r0, ggx_alpha(s.m), s.wo, l);
  switch (s.m.cls) {
    case MaterialClass::kDiffuse:
      return lambert_eval(s.m.kd, s.wo, l);
    case MaterialClass::kPolished:
      return coupled_diffuse_eval(s.m.kd, s.m.r0, s.wo, l);
    case MaterialClass::kMetal:
      return ggx_metal(s.m) ? ggx_eval(s.m.ks, ggx_alpha(s.m), s.wo, l) : Vec3(0.0f);
    default:
      return Vec3(0.0f);
  }
}

Vec3 path_eval_light_lobes(const PathSurface& s, const Vec3& wi) {
  if (s.m.cls == MaterialClass::kDiffuse || glm::dot(wi, s.ng) <= 0.0f) return Vec3(0.0f);
  const Vec3 l = s.frame.to_local(wi);
  const Vec3 k = s.m.cls == MaterialClass::kMetal ? s.m.ks : s.m.kh;
  return phong_eval(k, s.m.phong_exponent, s.wo, l);
}

float path_pdf(const PathSurface& s, const Vec3& wi) {
  if (glm::dot(wi, s.ng) <= 0.0f) return 0.0f;
  float pdf = 0.0f;
  if (s.m.cls == MaterialClass::kShader) return plugin_eval(s, wi, pdf), pdf;
  const Vec3 l = s.frame.to_local(wi);
  if (ggx_coated(s.m)) return ggx_coated_pdf(s.m.r0, ggx_alpha(s.m), s.wo, l);
  switch (s.m.cls) {
    case MaterialClass::kDiffuse:
      return lambert_pdf(s.wo, l);
    case MaterialClass::kPolished:
      return (1.0f - coat_probability(s)) * lambert_pdf(s.wo, l);
    case MaterialClass::kMetal:
      return ggx_metal(s.m) ? ggx_pdf(ggx_alpha(s.m), s.wo, l) : 0.0f;
    default:
      return 0.0f;
  }
}

bool path_sample(const PathSurface& s, float u0, float u1, float u2, PathScatter& out) {
  out = PathScatter{};
  if (ggx_coated(s.m)) {
    const BsdfSample b = ggx_coated_sample(s.m.kd, s.m.r0, ggx_alpha(s.m), s.wo, u0, u1, u2);
    out.wi = s.frame.to_world(b.wi);
    out.weight = b.weight;
    out.pdf = b.pdf;
    return glm::dot(out.wi, s.ng) > 0.0f && max_component(out.weight) > 0.0f && is_finite(out.weight);
  }
  switch (s.m.cls) {
    case MaterialClass::kShader: {  // a plug-in's own BSDF (attach_plugin_bsdf)
      fl_bsdf_sample b{};
      const PluginBsdf& p = *s.plugin;
      if (!p.shader->sample(&p.host, &p.hit, p.params,
                            fl_vec3{s.wo_world.x, s.wo_world.y, s.wo_world.z}, u1, u2, &b))
        return false;
      out.wi = Vec3(b.wi.x, b.wi.y, b.wi.z);
      out.weight = Vec3(b.weight.x, b.weight.y, b.weight.z);
      out.pdf = std::isfinite(b.pdf) && b.pdf > 0.0f ? b.pdf : 0.0f;
      out.delta = out.pdf == 0.0f;
      const float len = glm::length(out.wi);
      if (!(std::abs(len - 1.0f) < 1e-3f) || out.weight.x < 0.0f || out.weight.y < 0.0f || out.weight.z < 0.0f) return false;
      break;
    }
    case MaterialClass::kDiffuse: {
      const BsdfSample b = lambert_sample(s.m.kd, s.wo, u1, u2);
      out.wi = s.frame.to_world(b.wi);
      out.weight = b.weight;
      out.pdf = b.pdf;
      break;
    }
    case MaterialClass::kMetal:
      if (ggx_metal(s.m)) {
        const BsdfSample b = ggx_sample(s.m.ks, ggx_alpha(s.m), s.wo, u1, u2);
        out.wi = s.frame.to_world(b.wi);
        out.weight = b.weight;
        out.pdf = b.pdf;
        break;
      }
      out.wi = mirror_world(s);
      out.weight = s.m.ks;
      out.delta = true;
      break;
    case MaterialClass::kDielectric: {
      const float cos_i = cos_out(s);
      // Entering through the outward side goes from air (1) into the material (ior).
      const float eta = s.front_face ? 1.0f / s.m.ior : s.m.ior;
      const FresnelTerms f = dielectric_fresnel(cos_i, eta, r0_from_ior(s.m.ior));
      out.delta = true;
      // Reflect with probability k_s, refract with k_t = 1 - k_s: the weight is then 1.
      if (f.total_internal_reflection || u0 < f.ks) {
        out.wi = mirror_world(s);
        out.weight = Vec3(1.0f);
      } else {
        const Vec3 n = s.frame.n;
        out.wi = glm::normalize(eta * -s.wo_world + (eta * cos_i - f.cos_t) * n);
        out.weight = Vec3(1.0f);
        out.transmitted = true;
        return glm::dot(out.wi, s.ng) < 0.0f;
      }
      break;
    }
    case MaterialClass::kPolished: {
      const float p = coat_probability(s);
      if (u0 < p) {
        out.wi = mirror_world(s);
        out.weight = schlick(cos_out(s), s.m.r0) / p;
        out.delta = true;
      } else {
        const Vec3 l = sample_cosine_hemisphere(u1, u2);
        out.wi = s.frame.to_world(l);
        out.pdf = (1.0f - p) * lambert_pdf(s.wo, l);
        if (out.pdf > 0.0f)
          out.weight = coupled_diffuse_eval(s.m.kd, s.m.r0, s.wo, l) * (l.z / out.pdf);
      }
      break;
    }
  }
  // Reflections must leave on the viewer's side of the geometric surface.
  if (glm::dot(out.wi, s.ng) <= 0.0f) return false;
  return max_component(out.weight) > 0.0f && is_finite(out.weight);
}

}  // namespace frameless
