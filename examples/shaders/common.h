/* Small vector helpers shared by the example shaders (plain C, header only). */
#ifndef FRAMELESS_EXAMPLE_COMMON_H
#define FRAMELESS_EXAMPLE_COMMON_H
#include <math.h>

#include "frameless/shader.h"

static inline fl_vec3 v3(float x, float y, float z) { fl_vec3 r = {x, y, z}; return r; }
static inline fl_vec3 add(fl_vec3 a, fl_vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline fl_vec3 scale(fl_vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline fl_vec3 mul(fl_vec3 a, fl_vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline float dot(fl_vec3 a, fl_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline fl_vec3 normalize(fl_vec3 a) {
  const float l = sqrtf(dot(a, a));
  return l > 0.0f ? scale(a, 1.0f / l) : a;
}
static inline fl_vec3 param3(const float* p) { return v3(p[0], p[1], p[2]); }
static inline fl_vec3 mix3(fl_vec3 a, fl_vec3 b, float t) { return add(scale(a, 1.0f - t), scale(b, t)); }
static inline float clamp01(float x) { return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x; }

/* A diffuse surface of colour c, lit by the scene's ambient and lights (with their shadows). */
typedef struct {
  fl_vec3 sum;
} example_light_sum;
static inline void example_add_light(void* user, fl_vec3 radiance, fl_vec3 l, float n_dot_l) {
  example_light_sum* s = (example_light_sum*)user;
  (void)l;
  s->sum = add(s->sum, scale(radiance, n_dot_l));
}
static inline fl_vec3 lit_diffuse(const fl_host* host, const fl_hit* hit, fl_vec3 c) {
  example_light_sum s = {host->ambient(host->ctx, hit->shading_normal)};
  host->for_each_light(host->ctx, example_add_light, &s);
  return mul(c, s.sum);
}

/* Lambert's BSDF of colour c for path tracing: f = c / pi, cosine-weighted sampling around the
 * shading normal (which faces wo). */
static inline fl_vec3 lambert_eval(const fl_hit* hit, fl_vec3 c, fl_vec3 wi, float* pdf) {
  const float cos_i = dot(hit->shading_normal, wi);
  *pdf = cos_i > 0.0f ? cos_i / 3.14159265f : 0.0f;
  return cos_i > 0.0f ? scale(c, 1.0f / 3.14159265f) : v3(0.0f, 0.0f, 0.0f);
}
static inline int lambert_sample(const fl_hit* hit, fl_vec3 c, float u1, float u2, fl_bsdf_sample* out) {
  const float r = sqrtf(u1), phi = 6.28318531f * u2, z = sqrtf(1.0f - u1 > 0.0f ? 1.0f - u1 : 0.0f);
  out->wi = normalize(add(add(scale(hit->tangent, r * cosf(phi)), scale(hit->bitangent, r * sinf(phi))),
                          scale(hit->shading_normal, z)));
  out->pdf = z / 3.14159265f;
  out->weight = c; /* (c / pi) cos / (cos / pi) */
  return z > 0.0f;
}
#endif
