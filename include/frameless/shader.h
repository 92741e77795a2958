/* frameless plug-in shaders, interface version 1 (issue 28; docs/shaders.md).
 *
 * A shader is a shared library that exports one C function, frameless_shader_v1, returning a
 * description of the shader: its name, its parameters (names, types, ranges, defaults: the
 * scene's "params" are checked against them, so a typo is an error) and its functions. Scenes name
 * it from a material: "materials": {"bricks": {"shader": "bricks", "params": {...}}}; frameless
 * looks for NAME.so (or libNAME.so) on --shader-path, then FRAMELESS_SHADER_PATH, then next to
 * the scene file, and loads each library once.
 *
 * A plug-in is trusted code: it runs inside frameless, on every render thread at once, so shade()
 * must be reentrant (no writable globals) and must not keep the pointers it is given.
 *
 * This header is all a shader needs: plain C, no frameless library to link. Compile with
 *   cc -O2 -shared -fPIC -I<frameless>/include myshader.c -o myshader.so
 */
#ifndef FRAMELESS_SHADER_H
#define FRAMELESS_SHADER_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FRAMELESS_SHADER_API_VERSION 1u

typedef struct fl_vec3 {
  float x, y, z;
} fl_vec3;

/* What the shader receives for one ray hit. Vectors are in world space and unit length. */
typedef struct fl_hit {
  fl_vec3 position;
  fl_vec3 geometric_normal; /* facing the incoming ray */
  fl_vec3 shading_normal;   /* interpolated or mapped; same hemisphere as geometric_normal */
  fl_vec3 direction;        /* the incoming ray's direction (towards the surface) */
  float u, v;               /* texture coordinates where the primitive has them, else 0 */
  int front_face;           /* 1: the ray hit the outward side */
  int depth;                /* 0 for camera rays, +1 per reflection or refraction */
} fl_hit;

/* What the shader may call, always through the host it is given (ctx is the host's own). */
typedef void (*fl_light_visitor)(void* user, fl_vec3 radiance, fl_vec3 direction, float n_dot_l);
typedef struct fl_host {
  uint32_t api_version;
  void* ctx;
  /* Calls visit once per light that faces the point and is not fully shadowed (the scene's
   * shadow mode, soft or area, applies): the light's radiance times its visibility, the unit
   * direction towards it, and n.l with the shading normal. */
  void (*for_each_light)(void* ctx, fl_light_visitor visit, void* user);
  /* The scene's ambient light arriving around normal n (Parker's l_a). */
  fl_vec3 (*ambient)(void* ctx, fl_vec3 n);
  /* Radiance arriving along a secondary ray from the hit point. The ray leaves on the side of
   * the surface its direction points to; weight is the share the result will get in the pixel
   * (rays whose weight falls below the scene's threshold, or beyond the depth limit, return 0). */
  fl_vec3 (*trace)(void* ctx, fl_vec3 direction, fl_vec3 weight);
  /* A uniform random number in [0, 1) from the sample's own stream. */
  float (*random)(void* ctx);
} fl_host;

typedef enum fl_param_type {
  FL_PARAM_FLOAT = 1, /* one number */
  FL_PARAM_COLOR = 3  /* three numbers, [r, g, b] in the scene */
} fl_param_type;

/* One declared parameter: values in [min, max] (each component of a colour). */
typedef struct fl_param {
  const char* name;
  fl_param_type type;
  float min, max;
  float default_value[3]; /* [0] for FL_PARAM_FLOAT */
  const char* help;
} fl_param;

typedef struct fl_shader {
  uint32_t api_version; /* FRAMELESS_SHADER_API_VERSION */
  const char* name;
  const char* description;
  const fl_param* params;
  uint32_t param_count;
  /* Whitted-style shading (Parker's model): the radiance leaving the hit towards the viewer.
   * params holds the material's values in declaration order (1 float per FL_PARAM_FLOAT, 3 per
   * FL_PARAM_COLOR). Required. */
  fl_vec3 (*shade)(const fl_host* host, const fl_hit* hit, const float* params);
  /* Path tracing and instant global illumination treat the surface as Lambertian with this
   * albedo (each component in [0, 1]), evaluated once per material at load; NULL: 0.5 grey. */
  fl_vec3 (*albedo)(const float* params);
} fl_shader;

/* The one symbol a shader library exports. */
typedef const fl_shader* (*fl_shader_entry)(void);
#define FRAMELESS_SHADER_ENTRY "frameless_shader_v1"

#if defined(_WIN32)
#define FL_EXPORT __declspec(dllexport)
#else
#define FL_EXPORT __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
}
#endif

#endif /* FRAMELESS_SHADER_H */
