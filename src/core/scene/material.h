// Parker et al. 1999 material classes (section 3.1); read-only data, any thread.
#pragma once
#include <string>

#include "core/base/types.h"
#include "core/scene/texture.h"

namespace frameless {

// kShader: a plug-in shader (Scene::shaders[shader]) shades it for Whitted; path tracing and igi
// read it as diffuse with kd = the shader's albedo.
enum class MaterialClass : uint8_t { kDiffuse, kMetal, kDielectric, kPolished, kShader };

// One record for all classes; each class reads only the fields it needs:
//  diffuse:    kd                              (k_h = k_s = k_t = 0)
//  metal:      ks (k_h = k_s), phong_exponent  (k_d = k_t = 0)
//  dielectric: ior (R0 for Schlick), extinction kappa, kh + phong_exponent (highlight)
//  polished:   kd, r0 (Schlick R0 of the coat), kh + phong_exponent   (equation 2)
// Texture slots (indices into Scene::textures, kNoTexture when constant) replace the constant
// colours kd, kh, a metal's ks and the emission; alpha cuts the surface out where it falls
// below alpha_cutoff;
// normal_tex (tangent space, glTF) or bump_tex (height, OBJ bump) perturb the shading normal.
struct MaterialParams {
  MaterialClass cls = MaterialClass::kDiffuse;
  Vec3 kd{0.8f};
  Vec3 ks{0.0f};
  Vec3 kh{0.0f};
  float phong_exponent = 32.0f;
  float ior = 1.5f;
  Vec3 extinction{0.0f};  // kappa per unit length inside a dielectric, per channel
  Vec3 r0{0.04f};         // polished: Schlick normal-incidence reflectance of the coat
  // Radiance the surface emits (any class, both sides), added where a ray hits it: an area
  // light seen directly and in reflections.
  Vec3 emission{0.0f};

  uint32_t kd_tex = kNoTexture;      // multiplies kd
  uint32_t kh_tex = kNoTexture;      // multiplies kh
  uint32_t ks_tex = kNoTexture;      // multiplies a metal's ks
  uint32_t alpha_tex = kNoTexture;   // cut-out: channel alpha_channel times opacity
  uint32_t normal_tex = kNoTexture;  // tangent-space normal map
  uint32_t bump_tex = kNoTexture;    // height map (channel 0), scaled by bump_scale
  uint32_t emission_tex = kNoTexture;  // multiplies emission
  uint8_t alpha_channel = 3;         // 3: the texture's alpha; 0: its first channel (map_d)
  float opacity = 1.0f;              // constant alpha (glTF baseColorFactor.a, MTL d)
  float alpha_cutoff = 0.5f;         // alpha below this: the surface is absent for every ray
  float bump_scale = 1.0f;
  // glTF metallic-roughness metals: their roughness, read by the path tracer as GGX with
  // alpha = roughness^2 and f0 = k_s (Whitted keeps the Phong lobe derived from it). < 0: none.
  float roughness = -1.0f;
  uint16_t shader = 0;  // kShader: index into Scene::shaders

  bool textured() const {
    return kd_tex != kNoTexture || kh_tex != kNoTexture || ks_tex != kNoTexture ||
           normal_tex != kNoTexture || bump_tex != kNoTexture || emission_tex != kNoTexture;
  }
  bool cutout() const { return alpha_tex != kNoTexture || opacity < alpha_cutoff; }
};

// The parameters plus a name (scene files refer to materials by name). Shading works on the
// plain parameters, so a textured hit copies them without touching the string.
struct Material : MaterialParams {
  std::string name;
};

const char* material_class_name(MaterialClass c);

}  // namespace frameless
