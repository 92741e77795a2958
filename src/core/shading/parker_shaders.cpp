// Parker's classes through the plug-in interface: declarations, the compiled materials they
// stand for, and shade() written against the host alone (equations 1 and 2 of the seed).
#include "core/shading/parker_shaders.h"

#include <algorithm>
#include <cmath>

#include "core/shading/optics.h"
#include "core/shading/plugin_hit.h"

namespace frameless {
namespace {

constexpr float kBig = 1e6f;
const fl_param kDiffuseParams[] = {{"kd", FL_PARAM_COLOR, 0.0f, kBig, {0.8f, 0.8f, 0.8f}, "diffuse colour k_d"}};
const fl_param kMetalParams[] = {{"ks", FL_PARAM_COLOR, 0.0f, kBig, {0.9f, 0.9f, 0.9f}, "mirror colour k_s (= k_h)"},
                                 {"phong_exponent", FL_PARAM_FLOAT, 0.0f, kBig, {32.0f}, "highlight exponent N"}};
const fl_param kDielectricParams[] = {{"ior", FL_PARAM_FLOAT, 1e-3f, 100.0f, {1.5f}, "index of refraction"},
                                      {"extinction", FL_PARAM_COLOR, 0.0f, kBig, {0, 0, 0}, "absorption kappa per unit length"},
                                      {"kh", FL_PARAM_COLOR, 0.0f, kBig, {1, 1, 1}, "highlight colour k_h"},
                                      {"phong_exponent", FL_PARAM_FLOAT, 0.0f, kBig, {32.0f}, "highlight exponent N"}};
const fl_param kPolishedParams[] = {{"kd", FL_PARAM_COLOR, 0.0f, kBig, {0.8f, 0.8f, 0.8f}, "base colour k_d"},
                                    {"r0", FL_PARAM_COLOR, 0.0f, 1.0f, {0.04f, 0.04f, 0.04f}, "the coat's Schlick R0"},
                                    {"kh", FL_PARAM_COLOR, 0.0f, kBig, {1, 1, 1}, "highlight colour k_h"},
                                    {"phong_exponent", FL_PARAM_FLOAT, 0.0f, kBig, {32.0f}, "highlight exponent N"}};

Vec3 p3(const float* p) { return Vec3(p[0], p[1], p[2]); }
Vec3 mirror_of(const fl_hit* h) {
  return mirror_direction(from_fl(h->direction), from_fl(h->shading_normal), from_fl(h->geometric_normal));
}
Vec3 trace(const fl_host* host, const Vec3& d, const Vec3& w) { return from_fl(host->trace(host->ctx, to_fl(d), to_fl(w))); }

// Sums over the visible lights, handed to for_each_light.
struct LightSum {
  Vec3 n, e, kh, kd_term{0.0f}, highlight{0.0f};
  float view_factor = 1.0f, exponent = 0.0f;
  bool coupled = false;  // polished's (1 - (1 - n.l)^5) instead of n.l
};
void visit(void* user, fl_vec3 radiance, fl_vec3 dir, float nl) {
  LightSum& s = *static_cast<LightSum*>(user);
  const Vec3 le = from_fl(radiance), l = from_fl(dir);
  s.kd_term += le * (s.coupled ? s.view_factor * (1.0f - pow5(1.0f - nl)) : nl);
  if (max_component(s.kh) > 0.0f) s.highlight += le * s.kh * phong_lobe(s.n, s.e, l, s.exponent);
}

fl_vec3 shade_diffuse(const fl_host* host, const fl_hit* h, const float* p) {
  LightSum s{from_fl(h->shading_normal), -from_fl(h->direction), Vec3(0.0f)};
  host->for_each_light(host->ctx, visit, &s);
  return to_fl(p3(p) * (from_fl(host->ambient(host->ctx, h->shading_normal)) + s.kd_term));
}

fl_vec3 shade_metal(const fl_host* host, const fl_hit* h, const float* p) {
  const Vec3 ks = p3(p);
  LightSum s{from_fl(h->shading_normal), -from_fl(h->direction), ks};
  s.exponent = p[3];
  host->for_each_light(host->ctx, visit, &s);
  return to_fl(s.highlight + ks * trace(host, mirror_of(h), ks));
}

fl_vec3 shade_dielectric(const fl_host* host, const fl_hit* h, const float* p) {
  const Vec3 ns = from_fl(h->shading_normal), d = from_fl(h->direction);
  const float ior = p[0];
  const float cos_i = std::clamp(glm::dot(-d, ns), 0.0f, 1.0f);
  const float eta = h->front_face ? 1.0f / ior : ior;
  const FresnelTerms f = dielectric_fresnel(cos_i, eta, r0_from_ior(ior));
  LightSum s{ns, -d, p3(p + 4)};
  s.exponent = p[7];
  host->for_each_light(host->ctx, visit, &s);
  Vec3 out = s.highlight + f.ks * trace(host, mirror_of(h), Vec3(f.ks));
  if (!f.total_internal_reflection)  // the interface has no media: no absorption inside
    out += f.kt * trace(host, eta * d + (eta * cos_i - f.cos_t) * ns, Vec3(f.kt));
  return to_fl(out);
}

fl_vec3 shade_polished(const fl_host* host, const fl_hit* h, const float* p) {
  const Vec3 ns = from_fl(h->shading_normal), e = -from_fl(h->direction), kd = p3(p);
  const float en = std::clamp(glm::dot(e, ns), 0.0f, 1.0f);
  const Vec3 ks = schlick(en, p3(p + 3));
  LightSum s{ns, e, p3(p + 6)};
  s.exponent = p[9];
  s.coupled = true;
  s.view_factor = 1.0f - pow5(1.0f - en);
  host->for_each_light(host->ctx, visit, &s);
  const Vec3 ambient = from_fl(host->ambient(host->ctx, h->shading_normal));
  return to_fl(kd * ambient * (Vec3(1.0f) - ks) + kd * s.kd_term + s.highlight + ks * trace(host, mirror_of(h), ks));
}

fl_vec3 albedo_kd(const float* p) { return to_fl(glm::clamp(p3(p), Vec3(0.0f), Vec3(1.0f))); }

const fl_shader kShaders[kParkerShaders] = {
    {FRAMELESS_SHADER_API_VERSION, "diffuse", "Parker's diffuse class (built in)", kDiffuseParams, 1, shade_diffuse, albedo_kd, nullptr, nullptr},
    {FRAMELESS_SHADER_API_VERSION, "metal", "Parker's metal class (built in)", kMetalParams, 2, shade_metal, nullptr, nullptr, nullptr},
    {FRAMELESS_SHADER_API_VERSION, "dielectric", "Parker's dielectric class (built in)", kDielectricParams, 4, shade_dielectric, nullptr, nullptr, nullptr},
    {FRAMELESS_SHADER_API_VERSION, "polished", "Parker's polished class, equation 2 (built in)", kPolishedParams, 4, shade_polished, albedo_kd, nullptr, nullptr},
};
const fl_shader* const kTable[kParkerShaders] = {&kShaders[0], &kShaders[1], &kShaders[2], &kShaders[3]};

}  // namespace

const fl_shader* parker_shader(const std::string& name) {
  for (const fl_shader* s : kTable)
    if (name == s->name) return s;
  return nullptr;
}

const fl_shader* const* parker_shaders() { return kTable; }

Material parker_material(const fl_shader& shader, const float* p) {
  Material m;
  if (&shader == &kShaders[0]) {
    m.cls = MaterialClass::kDiffuse;
    m.kd = p3(p);
  } else if (&shader == &kShaders[1]) {
    m.cls = MaterialClass::kMetal;
    m.kd = Vec3(0.0f);
    m.ks = m.kh = p3(p);  // k_h = k_s (section 3.1)
    m.phong_exponent = p[3];
  } else if (&shader == &kShaders[2]) {
    m.cls = MaterialClass::kDielectric;
    m.kd = Vec3(0.0f);
    m.ior = p[0];
    m.extinction = p3(p + 1);
    m.kh = p3(p + 4);
    m.phong_exponent = p[7];
  } else {
    m.cls = MaterialClass::kPolished;
    m.kd = p3(p);
    m.r0 = p3(p + 3);
    m.kh = p3(p + 6);
    m.phong_exponent = p[9];
  }
  return m;
}

int route_through_interface(Scene& scene) {
  int n = 0;
  for (Material& m : scene.materials) {
    if (m.textured() || m.cutout() || max_component(m.emission) > 0.0f || m.roughness >= 0.0f) continue;
    ShaderMaterial bound;
    switch (m.cls) {
      case MaterialClass::kDiffuse: bound = {&kShaders[0], {m.kd.x, m.kd.y, m.kd.z}, "built in"}; break;
      case MaterialClass::kMetal: bound = {&kShaders[1], {m.ks.x, m.ks.y, m.ks.z, m.phong_exponent}, "built in"}; break;
      case MaterialClass::kDielectric:
        if (max_component(m.extinction) > 0.0f) continue;  // the interface has no media
        bound = {&kShaders[2], {m.ior, 0, 0, 0, m.kh.x, m.kh.y, m.kh.z, m.phong_exponent}, "built in"};
        break;
      case MaterialClass::kPolished:
        bound = {&kShaders[3], {m.kd.x, m.kd.y, m.kd.z, m.r0.x, m.r0.y, m.r0.z, m.kh.x, m.kh.y, m.kh.z, m.phong_exponent}, "built in"};
        break;
      default: continue;
    }
    if (scene.shaders.size() >= 65535) break;
    m.cls = MaterialClass::kShader;
    m.shader = uint16_t(scene.shaders.size());
    scene.shaders.push_back(std::move(bound));
    ++n;
  }
  return n;
}

}  // namespace frameless
