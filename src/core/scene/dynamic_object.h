// Objects that move while you look (seed section 4): kept out of the static acceleration
// structure and tested per ray, as RTRT did (core/scene/scene_intersect.h). Plain data of the
// scene, read-only while rendering.
#pragma once
#include <string>

#include "core/geometry/geometry.h"
#include "core/scene/motion.h"

namespace frameless {

// Hits on dynamic object i carry prim = kDynamicPrimBase + i.
inline constexpr uint32_t kDynamicPrimBase = 0xc0000000u;
inline bool is_dynamic_prim(uint32_t prim) { return prim >= kDynamicPrimBase && prim != kInvalidId; }

struct DynamicObject {
  std::string name;
  Sphere sphere;         // rest position and radius
  uint16_t material = 0;
  Motion motion;         // offset from the rest (or application-set) position as time passes
};

// An instance that moves: declared instance `index` translated from its declared placement.
struct InstanceMotion {
  uint32_t index = 0;
  Motion motion;
};

}  // namespace frameless
