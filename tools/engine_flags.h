// Engine and blend options shared by `view` and `capture`; main thread only.
#pragma once
#include <string>

#include <CLI/CLI.hpp>

#include "display/blend.h"
#include "frameless/engine_config.h"

namespace frameless::cli {

struct EngineFlags {
  int threads = 0;
  int chunk = 64;
  double update_percent = 1.0;
  uint64_t seed = 1;
  std::string mode = "frameless";
  float alpha = 0.5f;
  bool time_decay = false;
  // Frameless under motion (bench motion: reprojection and temporal weights win in the heavy
  // regime, and a still camera converges as fast; closed loop does not win yet: off).
  bool reproject = true;
  bool temporal = true;
  bool closed_loop = false;
  float reproject_budget = 0.0f;  // share of one core for reprojection (0: unlimited)
  double max_samples_per_s = 0.0; // frameless sample-rate cap (0: none)
  int render_nice = kDefaultRenderNice;  // render threads step aside for the display and the window
  bool no_jitter = false;
  bool no_packets = false;
  bool adaptive = false;
  bool denoise = false;
  bool no_discontinuity = false;
  void add_to(CLI::App& app);
  // Fills the engine and blend settings; false with a one-line message for a bad mode or alpha.
  // The caller still runs validate(engine) once it has set its own fields.
  bool apply(EngineConfig& engine, BlendConfig& blend, std::string& error) const;
};

// Across a cluster hit points do not cross the wire and clients serve no asks: reprojection
// and closed loop are off there (docs/cluster.md).
inline void fit_to_cluster(EngineConfig& engine, BlendConfig& blend) {
  engine.closed_loop = false;
  blend.reproject = false;
}

}  // namespace frameless::cli
