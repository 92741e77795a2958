// Parker's four material classes read physically, for the path tracer (docs/global-illumination.md):
//   diffuse    -> Lambertian, albedo k_d;
//   metal      -> a mirror tinted by k_s (glTF metals with a roughness: GGX, f0 = k_s);
//   dielectric -> Schlick-weighted mirror reflection and refraction (Beer absorption on the way);
//   polished   -> the coupled model of Shirley et al. 1997 under a Schlick coat of reflectance r0.
// Parker's highlights (metal's k_s, k_h of the other classes, exponent N) stand in for the mirror
// images of his lights, which a mirror cannot see (a point seen in a mirror is a delta of a delta),
// so here they become normalized Phong lobes that only Parker's lights are evaluated through.
// Emitting surfaces and the environment are seen in the mirrors themselves. Pure, any thread.
#pragma once
#include "core/geometry/shading_frame.h"
#include "core/geometry/surface.h"
#include "core/scene/material.h"
#include "frameless/shader.h"

namespace frameless {

// One hit's scattering: the material at the hit and its local frame around the shading normal.
struct PathSurface {
  MaterialParams m;
  ShadingFrame frame;  // around the shading normal (facing the incoming ray)
  Vec3 wo{0.0f};       // toward where the light goes (the previous vertex), local
  Vec3 wo_world{0.0f};
  Vec3 ng{0.0f};       // geometric normal, world, facing wo
  bool front_face = true;
  // A plug-in shader's BSDF (kShader with eval and sample; attach_plugin_bsdf sets it). A
  // pointer, so that the other materials' surfaces stay small.
  const struct PluginBsdf* plugin = nullptr;
};

// What a plug-in's eval() and sample() are called with; the caller keeps it alive.
struct PluginBsdf {
  const fl_shader* shader = nullptr;
  const float* params = nullptr;
  fl_hit hit{};
  fl_host host{};
};

// Hands a plug-in shaded surface to its shader's BSDF when it has one (kShader stays; without
// one make_path_surface has made it Lambertian with the shader's albedo).
void attach_plugin_bsdf(PathSurface& s, const MaterialParams& m, const PluginBsdf& bsdf);

PathSurface make_path_surface(const MaterialParams& m, const SurfacePoint& sp, const Vec3& wo_world);

// Whether the surface has a part that BSDF sampling covers with a density (diffuse, polished's
// base): only such surfaces gather light by next-event estimation.
bool path_is_smooth(const PathSurface& s);
// Whether Parker's lights are seen through highlight lobes (metal, or k_h > 0).
bool path_has_light_lobes(const PathSurface& s);

// f (no cosine) of the sampled, non-delta part toward world direction wi (unit).
Vec3 path_eval(const PathSurface& s, const Vec3& wi);
// f of the highlight lobes only Parker's lights are seen through.
Vec3 path_eval_light_lobes(const PathSurface& s, const Vec3& wi);
// Density per solid angle with which path_sample produces wi by its non-delta part.
float path_pdf(const PathSurface& s, const Vec3& wi);

struct PathScatter {
  Vec3 wi{0.0f};       // world, unit
  Vec3 weight{0.0f};   // f cos / pdf (delta parts: the reflectance or transmittance)
  float pdf = 0.0f;    // density of the non-delta part (0 for delta choices)
  bool delta = false;  // a mirror or refraction direction
  bool transmitted = false;  // crossed into (or out of) the dielectric
};

// The colour a denoiser divides out of a hit's light (and multiplies back): the diffuse
// colour, a metal's k_s, 1 for glass; clamped to [0, 1]. 0 for an emitter: the denoiser leaves
// it alone (its radiance would bleed into the surfaces around it).
Vec3 guide_albedo(const MaterialParams& m);

// Samples a direction with three uniform numbers in [0, 1); false when the path ends (below the
// surface, zero weight).
bool path_sample(const PathSurface& s, float u0, float u1, float u2, PathScatter& out);

}  // namespace frameless
