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

typedef struct fl_vec4 {
  float x, y, z, w;
} fl_vec4;

/* What the shader receives for one ray hit. Vectors are in world space and unit length. */
typedef struct fl_hit {
  fl_vec3 position;
  fl_vec3 geometric_normal; /* facing the incoming ray */
  fl_vec3 shading_normal;   /* interpolated or mapped; same hemisphere as geometric_normal */
  fl_vec3 direction;        /* the incoming ray's direction (towards the surface) */
  float u, v;               /* texture coordinates where the primitive has them, else 0 */
  int front_face;           /* 1: the ray hit the outward side */
  int depth;                /* 0 for camera rays, +1 per reflection or refraction */
  /* A frame around shading_normal: tangent along increasing u where the primitive has texture
   * coordinates (else any), bitangent = cross(shading_normal, tangent) flipped where the uv
   * layout is mirrored. Both unit and perpendicular to shading_normal. */
  fl_vec3 tangent;
  fl_vec3 bitangent;
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
  /* Perlin's improved noise (2002) at p, in [-1, 1], and turbulence: the sum over octaves of
   * |noise(2^k p)| / 2^k (the solid textures' building blocks; pure functions). */
  float (*noise)(fl_vec3 p);
  float (*turbulence)(fl_vec3 p, int octaves);
  /* The texture a FL_PARAM_TEXTURE parameter names (pass its value as `slot`), looked up at
   * texture coordinates (u, v) or, for the scene's solid textures, at point p: linear RGBA
   * (w = 1 where the image has no alpha). A parameter naming no texture gives (0, 0, 0, 0). */
  fl_vec4 (*texture)(void* ctx, float slot, float u, float v, fl_vec3 p);
} fl_host;

typedef enum fl_param_type {
  FL_PARAM_FLOAT = 1,  /* one number */
  FL_PARAM_COLOR = 3,  /* three numbers, [r, g, b] in the scene */
  FL_PARAM_TEXTURE = 4 /* the name of one of the scene's "textures" (or none): one slot value */
} fl_param_type;

/* One declared parameter: values in [min, max] (each component of a colour; ignored for
 * textures). */
typedef struct fl_param {
  const char* name;
  fl_param_type type;
  float min, max;
  float default_value[3]; /* [0] for FL_PARAM_FLOAT */
  const char* help;
} fl_param;

/* One sampled direction of a shader's BSDF (path tracing). */
typedef struct fl_bsdf_sample {
  fl_vec3 wi;     /* unit, world space, towards where the light comes from */
  fl_vec3 weight; /* f(wo, wi) |n . wi| / pdf: what the path's throughput is multiplied by */
  float pdf;      /* density per solid angle; 0 for a delta choice (a mirror direction) */
} fl_bsdf_sample;

typedef struct fl_shader {
  uint32_t api_version; /* FRAMELESS_SHADER_API_VERSION */
  const char* name;
  const char* description;
  const fl_param* params;
  uint32_t param_count;
  /* Whitted-style shading (Parker's model): the radiance leaving the hit towards the viewer.
   * params holds the material's values in declaration order (1 float per FL_PARAM_FLOAT and
   * FL_PARAM_TEXTURE, 3 per FL_PARAM_COLOR). Required. */
  fl_vec3 (*shade)(const fl_host* host, const fl_hit* hit, const float* params);
  /* Path tracing and instant global illumination treat the surface as Lambertian with this
   * albedo (each component in [0, 1]) unless the shader has eval and sample below; evaluated
   * once per material at load; NULL: 0.5 grey. */
  fl_vec3 (*albedo)(const float* params);
  /* Path tracing's BSDF, optional (both or neither; without them path tracing reads the surface
   * as Lambertian with albedo(), and instant global illumination always does). wo is the unit
   * direction towards where the light goes (the previous vertex), wi towards where it comes
   * from, both in world space. eval returns f(wo, wi) without the cosine and sets *pdf to the
   * density with which sample produces wi (0 where it never does); sample draws wi from two
   * uniform numbers and returns 0 when the path ends there. Directions below the geometric
   * surface are refused by frameless. Here the host's noise, turbulence and texture work;
   * for_each_light visits nothing, ambient and trace return 0, random returns 0. */
  fl_vec3 (*eval)(const fl_host* host, const fl_hit* hit, const float* params, fl_vec3 wo, fl_vec3 wi, float* pdf);
  int (*sample)(const fl_host* host, const fl_hit* hit, const float* params, fl_vec3 wo, float u1, float u2,
                fl_bsdf_sample* out);
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
