/* A toon shader: diffuse light quantized into a few flat bands, a hard highlight, and a dark
 * outline where the surface turns away from the viewer (the silhouette), which also shows in
 * reflections because it depends only on the ray that sees the point. */
#include "common.h"

static const fl_param params[] = {
    {"color", FL_PARAM_COLOR, 0.0f, 1.0f, {0.2f, 0.5f, 0.9f}, "the flat colour"},
    {"bands", FL_PARAM_FLOAT, 1.0f, 16.0f, {3.0f}, "how many tones between dark and lit"},
    {"outline", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.25f}, "silhouette width: outline where |n.e| is below it"},
    {"highlight", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.95f}, "h.n above which the highlight is white (1: none)"},
};

typedef struct {
  fl_vec3 n, e;
  float light, spec;
} toon_state;

static void light(void* user, fl_vec3 radiance, fl_vec3 l, float n_dot_l) {
  toon_state* s = (toon_state*)user;
  const float strength = (radiance.x + radiance.y + radiance.z) / 3.0f;
  s->light += strength * n_dot_l;
  const float hn = dot(normalize(add(l, s->e)), s->n);
  if (hn > s->spec) s->spec = hn;
}

static fl_vec3 shade(const fl_host* host, const fl_hit* hit, const float* p) {
  toon_state s = {hit->shading_normal, scale(hit->direction, -1.0f), 0.0f, 0.0f};
  if (fabsf(dot(s.n, s.e)) < p[4]) return v3(0.02f, 0.02f, 0.03f);
  const fl_vec3 amb = host->ambient(host->ctx, s.n);
  host->for_each_light(host->ctx, light, &s);
  const float lit = s.light < 0.0f ? 0.0f : s.light > 1.0f ? 1.0f : s.light;
  const float band = floorf(lit * p[3] + 0.5f) / p[3];
  fl_vec3 c = mul(param3(p), add(amb, v3(band, band, band)));
  if (p[5] < 1.0f && s.spec > p[5] && s.light > 0.0f) c = add(c, v3(0.6f, 0.6f, 0.6f));
  return c;
}

static fl_vec3 albedo(const float* p) { return param3(p); }

static const fl_shader toon = {FRAMELESS_SHADER_API_VERSION, "toon", "flat bands, a hard highlight and outlines",
                               params, sizeof params / sizeof params[0], shade, albedo};

FL_EXPORT const fl_shader* frameless_shader_v1(void) { return &toon; }
