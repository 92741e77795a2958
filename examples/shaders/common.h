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
#endif
