// Volume keys: isovalues up and down, transfer-function presets in turn.
#include "display/volume_keys.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <memory>

namespace frameless {
namespace {

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
      // The preset after the one in use (the first when the function is the scene's own points).
      const auto& presets = TransferFunction::kPresets;
      const int count = int(std::size(presets));
      int next = 0;
      for (int k = 0; k < count; ++k)
        if (v.tf->preset() == presets[k]) next = (k + 1) % count;
      v.set_transfer(std::make_shared<TransferFunction>(
          *TransferFunction::preset(presets[next], v.grid->min_value, v.grid->max_value, "transfer")));
      std::snprintf(line, sizeof line, "transfer function %s (B: next)", presets[next]);
    }
  }
  return line;
}

}  // namespace frameless
