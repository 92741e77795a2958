// Parker et al. 1999 material classes (section 3.1); read-only data, any thread.
#pragma once
#include <string>

#include "core/types.h"

namespace frameless {

enum class MaterialClass : uint8_t { kDiffuse, kMetal, kDielectric, kPolished };

// One record for all classes; each class reads only the fields it needs:
//  diffuse:    kd                              (k_h = k_s = k_t = 0)
//  metal:      ks (k_h = k_s), phong_exponent  (k_d = k_t = 0)
//  dielectric: ior (R0 for Schlick), extinction kappa, kh + phong_exponent (highlight)
//  polished:   kd, r0 (Schlick R0 of the coat), kh + phong_exponent   (equation 2)
struct Material {
  std::string name;
  MaterialClass cls = MaterialClass::kDiffuse;
  Vec3 kd{0.8f};
  Vec3 ks{0.0f};
  Vec3 kh{0.0f};
  float phong_exponent = 32.0f;
  float ior = 1.5f;
  Vec3 extinction{0.0f};  // kappa per unit length inside a dielectric, per channel
  Vec3 r0{0.04f};         // polished: Schlick normal-incidence reflectance of the coat
};

const char* material_class_name(MaterialClass c);

}  // namespace frameless
