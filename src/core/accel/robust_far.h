// The factor that makes a slab test conservative under rounding; shared by the BVH and the grid.
#pragma once

namespace frameless {

// Ize 2013, "Robust BVH ray traversal": widening tfar by 1 + 2 gamma(3) makes the slab test
// conservative under rounding, so a watertight triangle test is never culled by its box. We fold
// the factor into 1 / dir for the exit planes, which costs one more rounding: gamma(4).
inline constexpr float kRobustFar = 1.0f + 2.0f * (4.0f * 0x1p-24f) / (1.0f - 4.0f * 0x1p-24f);

}  // namespace frameless
