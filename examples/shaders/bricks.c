/* A procedural brick wall: running-bond courses of bricks with mortar between them, laid in a
 * plane of world space (the hit position's coordinates across the shading normal's dominant
 * axis), each brick's colour varied by a hash of its row and column; lit as a diffuse surface
 * (ambient plus the scene's lights with their shadows). */
#include "common.h"

static const fl_param params[] = {
    {"brick", FL_PARAM_COLOR, 0.0f, 1.0f, {0.55f, 0.2f, 0.12f}, "the bricks' colour"},
    {"mortar", FL_PARAM_COLOR, 0.0f, 1.0f, {0.75f, 0.73f, 0.68f}, "the mortar's colour"},
    {"width", FL_PARAM_FLOAT, 1e-4f, 1e4f, {0.25f}, "a brick's length (world units)"},
    {"height", FL_PARAM_FLOAT, 1e-4f, 1e4f, {0.08f}, "a course's height"},
    {"joint", FL_PARAM_FLOAT, 0.0f, 0.5f, {0.08f}, "mortar width as a share of the course height"},
    {"variation", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.25f}, "how much bricks differ in brightness"},
};

static float hash2(int a, int b) {
  unsigned h = (unsigned)a * 73856093u ^ (unsigned)b * 19349663u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return (float)(h & 0xffffu) / 65535.0f;
}

/* The wall's colour at a point: brick or mortar. */
static fl_vec3 wall(const fl_hit* hit, const float* p) {
  const fl_vec3 n = hit->shading_normal, q = hit->position;
  const float ax = fabsf(n.x), ay = fabsf(n.y), az = fabsf(n.z);
  /* Coordinates in the plane: along the wall (s) and up it (t). */
  const float s = ax > az && ax > ay ? q.z : q.x;
  const float t = ay > ax && ay > az ? q.z : q.y;
  const float row = floorf(t / p[7]);
  const float shifted = s / p[6] + ((int)row & 1) * 0.5f;
  const float col = floorf(shifted);
  const float fs = (shifted - col) * p[6] / p[7], ft = t / p[7] - row; /* in course heights */
  const float j = p[8] * 0.5f;
  if (ft < j || ft > 1.0f - j || fs < j || fs > p[6] / p[7] - j) return param3(p + 3);
  const float k = 1.0f - p[9] * hash2((int)row, (int)col);
  return scale(param3(p), k);
}

typedef struct {
  fl_vec3 sum;
} diffuse_state;

static void light(void* user, fl_vec3 radiance, fl_vec3 l, float n_dot_l) {
  diffuse_state* s = (diffuse_state*)user;
  (void)l;
  s->sum = add(s->sum, scale(radiance, n_dot_l));
}

static fl_vec3 shade(const fl_host* host, const fl_hit* hit, const float* p) {
  diffuse_state s = {host->ambient(host->ctx, hit->shading_normal)};
  host->for_each_light(host->ctx, light, &s);
  return mul(wall(hit, p), s.sum);
}

static fl_vec3 albedo(const float* p) { /* brick and mortar by their shares of the wall */
  const float mortar = p[8] * (1.0f + p[7] / p[6]);
  return add(scale(param3(p), (1.0f - mortar) * (1.0f - 0.5f * p[9])), scale(param3(p + 3), mortar));
}

static const fl_shader bricks = {FRAMELESS_SHADER_API_VERSION, "bricks", "a procedural brick wall, lit as diffuse",
                                 params, sizeof params / sizeof params[0], shade, albedo};

FL_EXPORT const fl_shader* frameless_shader_v1(void) { return &bricks; }
