// Volume keys: isovalues up and down, transfer-function presets in turn.
#include "display/volume_keys.h"

#include <algorithm>
#include <cstdio>
#include <memory>

namespace frameless {
namespace {

constexpr const char* kPresets[] = {"ct-bone", "ct-skin", "grayscale", "hot", "cool-warm"};
constexpr int kPresetCount = 5;

bool has_mode(const Scene& s, bool iso) {
  for (const VolumeObject& v : s.volumes)
    if ((v.mode == VolumeMode::kIsosurface) == iso) return true;
  return false;
}

}  // namespace

bool is_volume_key(const Scene& scene, int key) {
  if (key == 'Z' || key == 'X') return has_mode(scene, true);
  if (key == 'B') return has_mode(scene, false);
  return false;
}

std::string edit_volumes(Scene& scene, int key) {
  if (!is_volume_key(scene, key)) return "";
  char line[160] = "";
  for (VolumeObject& v : scene.volumes) {
    if (v.mode == VolumeMode::kIsosurface && (key == 'Z' || key == 'X')) {
      const float span = v.grid->max_value - v.grid->min_value, step = 0.02f * (span > 0.0f ? span : 1.0f);
      for (float& iso : v.isovalues)
        iso = std::clamp(iso + (key == 'X' ? step : -step), v.grid->min_value, v.grid->max_value);
      std::snprintf(line, sizeof line, "isovalue %g (Z lower, X raise)", double(v.isovalues[0]));
    } else if (v.mode != VolumeMode::kIsosurface && key == 'B') {
      // The preset after the one in use (the first when the function is the scene's own).
      int next = 0;
      for (int k = 0; k < kPresetCount; ++k) {
        auto tf = TransferFunction::preset(kPresets[k], v.grid->min_value, v.grid->max_value, "transfer");
        if (tf && v.tf && tf->points().size() == v.tf->points().size() &&
            std::equal(tf->points().begin(), tf->points().end(), v.tf->points().begin(),
                       [](const TransferPoint& a, const TransferPoint& b) {
                         return a.value == b.value && a.color == b.color && a.opacity == b.opacity;
                       }))
          next = (k + 1) % kPresetCount;
      }
      v.set_transfer(std::make_shared<TransferFunction>(
          *TransferFunction::preset(kPresets[next], v.grid->min_value, v.grid->max_value, "transfer")));
      std::snprintf(line, sizeof line, "transfer function %s (B: next)", kPresets[next]);
    }
  }
  return line;
}

}  // namespace frameless
