// Scene analysis at load time and the choice of a specialised per-sample shading path; pure
// functions on a read-only scene, any thread.
#pragma once
#include <cstdint>
#include <string>

#include "core/scene/dynamic.h"
#include "core/scene/scene.h"

namespace frameless {

// Bits of a shading path: each set bit compiles one kind of work into the shading loop. A path
// without a bit can only be chosen when the scene provably needs none of that work, so the
// specialised path computes the same image as the general one (kShadeAll).
enum ShadeBits : uint32_t {
  kShadeLights = 1u,      // light loop and shadow rays
  kShadeRefraction = 2u,  // dielectric class: refraction, media tracking
  kShadeAbsorption = 4u,  // Beer's-law attenuation inside absorbing dielectrics
  kShadeHighlights = 8u,  // Phong lobes of metal, dielectric and polished materials
};
inline constexpr uint32_t kShadeAll = 15u;
inline constexpr uint32_t kShadePaths = 16u;  // number of compiled shading paths

// What `scene` needs: lights, primitive kinds, material classes, media, highlights, ambient.
SceneFeatures analyse_scene(const Scene& scene);

// The shading path for the scene's features under its SkipConfig: a switched-off skip keeps its
// bit set (the general code runs); a bit is cleared only when the feature is absent.
uint32_t shade_path(const SceneFeatures& features, const SkipConfig& skips);
inline uint32_t shade_path(const Scene& scene) {
  return shade_path(scene.features, scene.settings.skips);
}

// The path for a sample that sees `frame`'s lights and materials (changed while you look).
uint32_t frame_shade_path(const Scene& scene, const DynamicFrame& frame);

// "lights+refraction+absorption+highlights", or "minimal" for no bit (reports, benchmarks).
std::string describe_shade_path(uint32_t path);

}  // namespace frameless
