// Names and range checks of the engine settings.
#include "frameless/engine_config.h"

#include "frameless/adaptive.h"

namespace frameless {

const char* to_string(RenderMode mode) {
  return mode == RenderMode::frameless ? "frameless" : "conventional";
}

std::optional<RenderMode> parse_render_mode(const std::string& text) {
  if (text == "frameless") return RenderMode::frameless;
  if (text == "conventional") return RenderMode::conventional;
  return std::nullopt;
}

std::string validate(const EngineConfig& c) {
  if (c.width < 1 || c.width > 16384) return "width: must be 1..16384";
  if (c.height < 1 || c.height > 16384) return "height: must be 1..16384";
  if (c.threads < 0 || c.threads > 1024) return "threads: must be 0 (all cores) .. 1024";
  if (c.chunk_size < 1) return "chunk_size: must be at least 1";
  if (!(c.update_percent >= 0.01 && c.update_percent <= 100.0))
    return "update_percent: must be 0.01..100";
  if (std::string a = validate(c.adaptive); !a.empty()) return a;
  if (!(c.max_samples_per_s >= 0.0 && c.max_samples_per_s < 1e12))
    return "max_samples_per_s: must be 0 (no limit) or positive";
  if (c.motion_history < 2 || c.motion_history > 65536) return "motion_history: must be 2..65536";
  if (c.render_nice < 0 || c.render_nice > kMaxRenderNice) return "render_nice: must be 0..19";
  if (c.owned_count >= 0) {
    if (c.threads < 1) return "owned_count: needs an explicit thread count";
    if (c.owned_first < 0 || c.owned_first + c.owned_count > c.threads)
      return "owned_first: the owned threads must lie within 0..threads";
  } else if (c.owned_count != -1) {
    return "owned_count: must be -1 (all), 0 or more";
  }
  return "";
}

}  // namespace frameless
