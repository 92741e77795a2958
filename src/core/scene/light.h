// Point and spherical luminaires, and the ambient models of section 3.1.1; read-only, any thread.
#pragma once
#include <memory>

#include "core/base/types.h"
#include "core/scene/irradiance_volume.h"

namespace frameless {

enum class LightKind : uint8_t { kPoint, kDirectional };

// Point light: radius == 0 is a point, radius > 0 a spherical light (soft shadows).
// Directional light (a sun): light arrives along -direction from infinitely far; angular_radius
// (radians) > 0 gives it a disk that casts soft shadows.
struct Light {
  Vec3 position{0.0f, 10.0f, 0.0f};
  Vec3 color{1.0f};
  float radius = 0.0f;
  LightKind kind = LightKind::kPoint;
  Vec3 direction{0.0f, -1.0f, 0.0f};  // unit, the direction the light travels (directional)
  float angular_radius = 0.0f;        // directional: half-angle of the sun's disk, radians
  bool has_extent() const { return kind == LightKind::kPoint ? radius > 0.0f : angular_radius > 0.0f; }
};

// How shadow rays estimate the visible fraction s of a light (docs/scene-format.md):
//  hard: one ray to the light's centre (s is 0 or 1);
//  soft: Parker, Shirley and Smits' single-sample soft shadows (one cone query per light);
//  area: the reference, shadow_samples rays spread over the cone the light subtends.
enum class ShadowMode : uint8_t { kHard, kSoft, kArea, kBeam };
const char* shadow_mode_name(ShadowMode m);

enum class AmbientKind : uint8_t { kNone, kConstant, kHemisphere, kIrradianceVolume };

// Constant ambient l_a, or the two-hemisphere ambient: colour A in the direction of `axis`,
// colour B opposite, blended by Nusselt's analog as a function of the angle to the axis; or the
// irradiance volume, l_a(p, n) = E(p, n) / pi.
struct Ambient {
  AmbientKind kind = AmbientKind::kConstant;
  Vec3 constant{0.1f};
  Vec3 a{0.2f};
  Vec3 b{0.05f};
  Vec3 axis{0.0f, 1.0f, 0.0f};  // unit
  // Irradiance volume: grid vertices along the scene's longest side, paths per vertex, and the
  // baked grid (null until core/shading/irradiance_bake.h fills it at load time).
  int volume_resolution = 12;
  int volume_samples = 1024;
  std::shared_ptr<const IrradianceVolume> volume;
};

}  // namespace frameless
