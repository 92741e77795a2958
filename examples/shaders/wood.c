/* Procedural wood: growth rings around an axis through `center` along y (world space), their
 * radius disturbed by the host's turbulence so that rings wander like grain, light and dark wood
 * mixed across each ring; a varnish highlight towards each light under Whitted shading. Path
 * tracing samples the wood's own colour at the hit (eval/sample: Lambertian, the varnish left
 * out). */
#include "common.h"

static const fl_param params[] = {
    {"light", FL_PARAM_COLOR, 0.0f, 1.0f, {0.72f, 0.5f, 0.3f}, "early wood's colour"},
    {"dark", FL_PARAM_COLOR, 0.0f, 1.0f, {0.42f, 0.24f, 0.12f}, "late wood's colour"},
    {"rings", FL_PARAM_FLOAT, 0.01f, 1000.0f, {12.0f}, "rings per world unit of radius"},
    {"distortion", FL_PARAM_FLOAT, 0.0f, 10.0f, {0.6f}, "how far turbulence moves the rings (in rings)"},
    {"grain", FL_PARAM_FLOAT, 0.01f, 1000.0f, {3.0f}, "the turbulence's frequency"},
    {"center", FL_PARAM_COLOR, -1e4f, 1e4f, {0.0f, 0.0f, 0.0f}, "a point on the trunk's axis (x, y, z)"},
    {"varnish", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.15f}, "the highlight's strength"},
    {"exponent", FL_PARAM_FLOAT, 1.0f, 1e5f, {40.0f}, "the highlight's Phong exponent"},
};

static fl_vec3 wood(const fl_host* host, const fl_hit* hit, const float* p) {
  const fl_vec3 q = v3(hit->position.x - p[9], hit->position.y - p[10], hit->position.z - p[11]);
  const float r = sqrtf(q.x * q.x + q.z * q.z) * p[6];
  const float d = p[7] * host->turbulence(scale(q, p[8]), 4);
  float ring = r + d - floorf(r + d);
  ring = ring * ring * (3.0f - 2.0f * ring); /* smooth from early to late wood */
  return mix3(param3(p), param3(p + 3), ring);
}

typedef struct {
  fl_vec3 sum, view, n;
  float exponent;
} varnish_state;

static void highlight(void* user, fl_vec3 radiance, fl_vec3 l, float n_dot_l) {
  varnish_state* s = (varnish_state*)user;
  const fl_vec3 h = normalize(add(l, s->view));
  const float c = dot(s->n, h);
  (void)n_dot_l;
  if (c > 0.0f) s->sum = add(s->sum, scale(radiance, powf(c, s->exponent)));
}

static fl_vec3 shade(const fl_host* host, const fl_hit* hit, const float* p) {
  fl_vec3 out = lit_diffuse(host, hit, wood(host, hit, p));
  if (p[12] > 0.0f) {
    varnish_state s = {v3(0, 0, 0), scale(hit->direction, -1.0f), hit->shading_normal, p[13]};
    host->for_each_light(host->ctx, highlight, &s);
    out = add(out, scale(s.sum, p[12]));
  }
  return out;
}

static fl_vec3 albedo(const float* p) { return scale(add(param3(p), param3(p + 3)), 0.5f); }

static fl_vec3 eval(const fl_host* host, const fl_hit* hit, const float* p, fl_vec3 wo, fl_vec3 wi, float* pdf) {
  (void)wo;
  return lambert_eval(hit, wood(host, hit, p), wi, pdf);
}

static int sample(const fl_host* host, const fl_hit* hit, const float* p, fl_vec3 wo, float u1, float u2,
                  fl_bsdf_sample* out) {
  (void)wo;
  return lambert_sample(hit, wood(host, hit, p), u1, u2, out);
}

static const fl_shader shader = {FRAMELESS_SHADER_API_VERSION, "wood", "procedural wood rings with a varnish highlight",
                                 params, sizeof params / sizeof params[0], shade, albedo, eval, sample};

FL_EXPORT const fl_shader* frameless_shader_v1(void) { return &shader; }
