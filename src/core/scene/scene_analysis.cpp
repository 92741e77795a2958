// Scene analysis and shading-path choice (docs/adaptive.md, "Skip what a scene doesn't need").
#include "core/scene/scene_analysis.h"

namespace frameless {

SceneFeatures analyse_scene(const Scene& scene) {
  SceneFeatures f;
  // A black light adds nothing and casts no visible shadow (s l_e = 0 either way): not a light.
  for (const Light& l : scene.lights) f.has_lights |= glm::dot(l.color, l.color) > 0.0f;
  f.has_spheres = !scene.geometry.spheres.empty() || !scene.dynamic.empty();
  f.has_dynamic = !scene.dynamic.empty();
  f.has_triangles = !scene.geometry.triangles.empty();
  f.has_vertex_normals = !scene.geometry.normals.empty();
  f.has_ambient = scene.ambient.kind != AmbientKind::kNone;
  for (const Material& m : scene.materials) {
    const bool dielectric = m.cls == MaterialClass::kDielectric;
    f.has_dielectric |= dielectric;
    f.has_absorption |= dielectric && glm::dot(m.extinction, m.extinction) > 0.0f;
    f.has_reflection |= m.cls != MaterialClass::kDiffuse;
    f.has_highlights |= m.cls != MaterialClass::kDiffuse && glm::dot(m.kh, m.kh) > 0.0f;
    f.has_highlights |= m.cls == MaterialClass::kMetal && glm::dot(m.ks, m.ks) > 0.0f;
  }
  for (const Material& m : scene.materials) {
    f.has_textures |= m.textured();
    f.has_cutouts |= m.cutout();
    f.has_emission |= max_component(m.emission) > 0.0f;
  }
  const bool extended = scene.settings.shadows != ShadowMode::kHard;
  for (const Light& l : scene.lights) f.has_soft_lights |= extended && l.has_extent();
  return f;
}

uint32_t shade_path(const SceneFeatures& f, const SkipConfig& skips) {
  uint32_t bits = kShadeAll;
  if (skips.shadows && !f.has_lights) bits &= ~kShadeLights;
  if (skips.refraction && !f.has_dielectric) bits &= ~(kShadeRefraction | kShadeAbsorption);
  if (skips.refraction && !f.has_absorption) bits &= ~kShadeAbsorption;
  // Without lights no lobe is ever evaluated, so the highlight code goes with the light loop.
  if (skips.highlights && (!f.has_highlights || !(bits & kShadeLights))) bits &= ~kShadeHighlights;
  return bits;
}

uint32_t frame_shade_path(const Scene& scene, const DynamicFrame& frame) {
  // Lights and materials changed while you look may switch on what the loaded scene lacked.
  SceneFeatures f = scene.features;
  for (const Light& l : frame.lights) f.has_lights |= glm::dot(l.color, l.color) > 0.0f;
  for (size_t i = 0; i < frame.materials.size() && i < scene.materials.size(); ++i) {
    const MaterialParams& m = frame.materials[i];
    f.has_highlights |= m.cls != MaterialClass::kDiffuse && glm::dot(m.kh, m.kh) > 0.0f;
    f.has_highlights |= m.cls == MaterialClass::kMetal && glm::dot(m.ks, m.ks) > 0.0f;
  }
  return shade_path(f, scene.settings.skips);
}

std::string describe_shade_path(uint32_t path) {
  std::string s;
  const char* names[] = {"lights", "refraction", "absorption", "highlights"};
  for (int b = 0; b < 4; ++b)
    if (path & (1u << b)) {
      if (!s.empty()) s += '+';
      s += names[b];
    }
  return s.empty() ? "minimal" : s;
}

}  // namespace frameless
