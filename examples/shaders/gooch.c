/* Gooch, Gooch, Shirley and Cohen 1998, "A Non-Photorealistic Lighting Model for Automatic
 * Technical Illustration" (the seed's reference [12]): cool-to-warm tones instead of dark
 * shading, k_cool = b + alpha k_d and k_warm = y + beta k_d blended by t = (1 + n.l) / 2, so
 * surfaces facing the light are warm and those facing away cool, plus a white Phong highlight.
 * Lights come with the scene's shadows; a point no light reaches is all cool. */
#include "common.h"

static const fl_param params[] = {
    {"kd", FL_PARAM_COLOR, 0.0f, 1.0f, {0.6f, 0.6f, 0.6f}, "the object's own colour"},
    {"blue", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.4f}, "b: the blue of the cool tone"},
    {"yellow", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.4f}, "y: the yellow of the warm tone"},
    {"alpha", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.2f}, "the object colour's share of the cool tone"},
    {"beta", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.6f}, "the object colour's share of the warm tone"},
    {"shininess", FL_PARAM_FLOAT, 0.0f, 10000.0f, {60.0f}, "Phong exponent of the highlight (0: none)"},
};

typedef struct {
  fl_vec3 n, e, sum;
  float weight, shininess;
} gooch_state;

static void light(void* user, fl_vec3 radiance, fl_vec3 l, float n_dot_l) {
  gooch_state* s = (gooch_state*)user;
  (void)n_dot_l;
  const float strength = (radiance.x + radiance.y + radiance.z) / 3.0f;
  s->weight += strength * 0.5f * (1.0f + dot(s->n, l));  /* t per light, weighted by its strength */
  s->sum.x += strength;
  if (s->shininess > 0.0f) {
    const fl_vec3 h = normalize(add(l, s->e));
    const float hn = dot(h, s->n);
    if (hn > 0.0f) s->sum.y += strength * powf(hn, s->shininess);
  }
}

static fl_vec3 shade(const fl_host* host, const fl_hit* hit, const float* p) {
  const fl_vec3 kd = param3(p);
  const fl_vec3 cool = add(v3(0.0f, 0.0f, p[3]), scale(kd, p[5]));
  const fl_vec3 warm = add(v3(p[4], p[4], 0.0f), scale(kd, p[6]));
  gooch_state s = {hit->shading_normal, scale(hit->direction, -1.0f), v3(0, 0, 0), 0.0f, p[7]};
  host->for_each_light(host->ctx, light, &s);
  const float t = s.sum.x > 0.0f ? s.weight / s.sum.x : 0.0f;
  return add(add(scale(warm, t), scale(cool, 1.0f - t)), v3(s.sum.y, s.sum.y, s.sum.y));
}

static fl_vec3 albedo(const float* p) { return param3(p); }

static const fl_shader gooch = {FRAMELESS_SHADER_API_VERSION, "gooch",
                                "Gooch et al.'s cool-to-warm technical illustration shading",
                                params, sizeof params / sizeof params[0], shade, albedo};

FL_EXPORT const fl_shader* frameless_shader_v1(void) { return &gooch; }
