// Names of the scene's enumerations (reports, JSON, the command line).
#include "core/scene/scene.h"

namespace frameless {

const char* material_class_name(MaterialClass c) {
  switch (c) {
    case MaterialClass::kDiffuse: return "diffuse";
    case MaterialClass::kMetal: return "metal";
    case MaterialClass::kDielectric: return "dielectric";
    case MaterialClass::kPolished: return "polished";
    case MaterialClass::kShader: return "shader";
  }
  return "unknown";
}

const char* shadow_mode_name(ShadowMode m) {
  switch (m) {
    case ShadowMode::kHard: return "hard";
    case ShadowMode::kSoft: return "soft";
    case ShadowMode::kArea: return "area";
    case ShadowMode::kBeam: return "beam";
  }
  return "unknown";
}

const char* integrator_name(Integrator i) {
  switch (i) {
    case Integrator::kAuto: return "auto";
    case Integrator::kWhitted: return "whitted";
    case Integrator::kPath: return "path";
    case Integrator::kIgi: return "igi";
  }
  return "unknown";
}

bool parse_integrator(const std::string& name, Integrator& out) {
  if (name == "whitted") out = Integrator::kWhitted;
  else if (name == "path") out = Integrator::kPath;
  else if (name == "igi") out = Integrator::kIgi;
  else return false;
  return true;
}

}  // namespace frameless
