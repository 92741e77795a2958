/* Deliberately broken plug-ins for the loader's tests (tests/core/shader_plugin_test.cpp), one
 * per compile definition: BROKEN_VERSION (built for interface 99), BROKEN_PARAMS (a range with
 * min > max), BROKEN_NO_ENTRY (no entry point), BROKEN_NAN (shade returns NaN; albedo fine),
 * BROKEN_HALF_BSDF (eval() without sample()). */
#include <math.h>

#include "frameless/shader.h"

static fl_vec3 shade(const fl_host* host, const fl_hit* hit, const float* params) {
  (void)host, (void)hit, (void)params;
  fl_vec3 r = {NAN, 1.0f, -1.0f};
  return r;
}

#ifdef BROKEN_HALF_BSDF
static fl_vec3 eval(const fl_host* host, const fl_hit* hit, const float* params, fl_vec3 wo, fl_vec3 wi, float* pdf) {
  (void)host, (void)hit, (void)params, (void)wo, (void)wi;
  *pdf = 0.0f;
  return wo;
}
#endif

#ifndef BROKEN_NO_ENTRY
static const fl_param params[] = {{"k", FL_PARAM_FLOAT, 0.0f, 1.0f, {0.5f}, ""}};
static const fl_param bad_params[] = {{"k", FL_PARAM_FLOAT, 1.0f, 0.0f, {0.5f}, ""}};
static const fl_shader shader = {
#ifdef BROKEN_VERSION
    99u,
#else
    FRAMELESS_SHADER_API_VERSION,
#endif
    "broken", "for tests",
#ifdef BROKEN_PARAMS
    bad_params,
#else
    params,
#endif
    1, shade, 0,
#ifdef BROKEN_HALF_BSDF
    eval, 0
#else
    0, 0
#endif
};
FL_EXPORT const fl_shader* frameless_shader_v1(void) { return &shader; }
#endif
