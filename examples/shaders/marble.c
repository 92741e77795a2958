/* Procedural marble (Perlin 1985): veins where sin(x frequency + amplitude turbulence(p)) is
 * near zero, the base colour elsewhere, optionally multiplied by a texture the scene names
 * ("tint": one of its "textures", image or solid); a polished highlight under Whitted shading.
 * Path tracing samples the marble's colour at the hit (eval/sample: Lambertian). */
#include "common.h"

static const fl_param params[] = {
    {"base", FL_PARAM_COLOR, 0.0f, 1.0f, {0.86f, 0.85f, 0.82f}, "the stone's colour"},
    {"vein", FL_PARAM_COLOR, 0.0f, 1.0f, {0.25f, 0.27f, 0.3f}, "the veins' colour"},
    {"frequency", FL_PARAM_FLOAT, 0.01f, 1000.0f, {4.0f}, "veins per world unit (along x)"},
    {"amplitude", FL_PARAM_FLOAT, 0.0f, 100.0f, {6.0f}, "how much turbulence bends the veins"},
    {"sharpness", FL_PARAM_FLOAT, 1.0f, 64.0f, {6.0f}, "how thin the veins are"},
    {"polish", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.2f}, "the highlight's strength"},
    {"tint", FL_PARAM_TEXTURE, 0.0f, 0.0f, {0.0f}, "a texture multiplying the colour (optional)"},
};

static fl_vec3 marble(const fl_host* host, const fl_hit* hit, const float* p) {
  const fl_vec3 q = hit->position;
  const float s = sinf(6.28318531f * p[6] * q.x + p[7] * host->turbulence(scale(q, p[6]), 6));
  const float vein = powf(1.0f - fabsf(s), p[8]);
  fl_vec3 c = mix3(param3(p), param3(p + 3), clamp01(vein));
  const fl_vec4 t = host->texture(host->ctx, p[10], hit->u, hit->v, hit->position);
  if (t.w > 0.0f) c = mul(c, v3(t.x, t.y, t.z));
  return c;
}

typedef struct {
  fl_vec3 sum, view, n;
} polish_state;

static void highlight(void* user, fl_vec3 radiance, fl_vec3 l, float n_dot_l) {
  polish_state* s = (polish_state*)user;
  const float c = dot(s->n, normalize(add(l, s->view)));
  (void)n_dot_l;
  if (c > 0.0f) s->sum = add(s->sum, scale(radiance, powf(c, 80.0f)));
}

static fl_vec3 shade(const fl_host* host, const fl_hit* hit, const float* p) {
  fl_vec3 out = lit_diffuse(host, hit, marble(host, hit, p));
  if (p[9] > 0.0f) {
    polish_state s = {v3(0, 0, 0), scale(hit->direction, -1.0f), hit->shading_normal};
    host->for_each_light(host->ctx, highlight, &s);
    out = add(out, scale(s.sum, p[9]));
  }
  return out;
}

static fl_vec3 albedo(const float* p) { return mix3(param3(p), param3(p + 3), 0.15f); }

static fl_vec3 eval(const fl_host* host, const fl_hit* hit, const float* p, fl_vec3 wo, fl_vec3 wi, float* pdf) {
  (void)wo;
  return lambert_eval(hit, marble(host, hit, p), wi, pdf);
}

static int sample(const fl_host* host, const fl_hit* hit, const float* p, fl_vec3 wo, float u1, float u2,
                  fl_bsdf_sample* out) {
  (void)wo;
  return lambert_sample(hit, marble(host, hit, p), u1, u2, out);
}

static const fl_shader shader = {FRAMELESS_SHADER_API_VERSION, "marble", "Perlin's marble veins, polished",
                                 params, sizeof params / sizeof params[0], shade, albedo, eval, sample};

FL_EXPORT const fl_shader* frameless_shader_v1(void) { return &shader; }
