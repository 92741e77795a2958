// The reflection depth view's false colour (seed figure 1d): how many reflection/refraction levels
// a pixel's newest update traced, as linear RGB (the viewer sRGB-encodes it like any image).
#pragma once
#include <cstdint>

#include "core/base/types.h"

namespace frameless {

// Levels at and above this many show as pure red.
inline constexpr uint32_t kLevelsRed = 25;

// Ramp: 0 dark blue, 1 blue, 2 cyan, 4 green, 8 yellow, 16 orange, 25+ red; linear in between.
inline Vec3 levels_color(uint32_t levels) {
  struct Stop {
    float level;
    Vec3 rgb;
  };
  static const Stop kStops[] = {
      {0.0f, Vec3(0.0f, 0.0f, 0.08f)},  {1.0f, Vec3(0.0f, 0.05f, 0.6f)},
      {2.0f, Vec3(0.0f, 0.45f, 0.8f)},  {4.0f, Vec3(0.05f, 0.7f, 0.1f)},
      {8.0f, Vec3(0.9f, 0.85f, 0.0f)},  {16.0f, Vec3(1.0f, 0.35f, 0.0f)},
      {float(kLevelsRed), Vec3(1.0f, 0.0f, 0.0f)}};
  constexpr int kCount = int(sizeof kStops / sizeof kStops[0]);
  if (levels >= kLevelsRed) return kStops[kCount - 1].rgb;
  const float l = float(levels);
  int k = 1;
  while (kStops[k].level < l) ++k;
  const Stop &a = kStops[k - 1], &b = kStops[k];
  const float t = (l - a.level) / (b.level - a.level);
  return a.rgb + (b.rgb - a.rgb) * t;
}

// One-line legend for overlays and help texts.
inline constexpr const char* kLevelsLegend =
    "0 dark blue, 1 blue, 2 cyan, 4 green, 8 yellow, 16 orange, 25+ red";

}  // namespace frameless
