// Point and spherical luminaires, and the ambient models of section 3.1.1; read-only, any thread.
#pragma once
#include "core/types.h"

namespace frameless {

// radius == 0 is a point light; radius > 0 is a spherical light (soft shadows use it later).
struct Light {
  Vec3 position{0.0f, 10.0f, 0.0f};
  Vec3 color{1.0f};
  float radius = 0.0f;
};

enum class AmbientKind : uint8_t { kNone, kConstant, kHemisphere };

// Constant ambient l_a, or the two-hemisphere ambient: colour A in the direction of `axis`,
// colour B opposite, blended by Nusselt's analog as a function of the angle to the axis.
struct Ambient {
  AmbientKind kind = AmbientKind::kConstant;
  Vec3 constant{0.1f};
  Vec3 a{0.2f};
  Vec3 b{0.05f};
  Vec3 axis{0.0f, 1.0f, 0.0f};  // unit
};

}  // namespace frameless
