// Basic math types for the core (GLM), shared by every thread.
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace frameless {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using UVec3 = glm::uvec3;

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr uint32_t kInvalidId = 0xffffffffu;

// Largest component (std::max: one maxss each, no libm call).
inline float max_component(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

inline bool is_finite(const Vec3& v) {
  // Bit-free check: finite values compare equal to themselves and stay below the max.
  constexpr float kMax = std::numeric_limits<float>::max();
  return v.x == v.x && v.y == v.y && v.z == v.z && v.x <= kMax && v.x >= -kMax &&
         v.y <= kMax && v.y >= -kMax && v.z <= kMax && v.z >= -kMax;
}

}  // namespace frameless
