// `frameless bench reproject`: the display thread's reprojection (display/reproject.h) alone, on
// one core with nothing else running: a scene's primary hits at every pixel, moved to an orbiting
// camera change after change, along the Hilbert curve (how the display keeps its image), in the
// engine's slot order (how it kept it before: a shuffle of the curve's 64-pixel chunks) and in
// plain pixel order. Its flags are in tools/bench_reproject_command.cpp.
#pragma once
#include <string>

namespace frameless::bench {

struct ReprojectOptions {
  std::string scene = "default";
  std::string size = "1280x720";
  int threads = 2;           // render threads whose slot order is measured
  double degrees = 0.5;      // orbit per camera change (15 degrees a second at 30 Hz)
  int changes = 30;          // timed reprojections per order; the median is reported
  std::string order = "all";  // "curve", "slots", "pixels" or all
  int evict_mb = 0;          // megabytes of other memory written between changes (0: none)
  bool json = false;
};

int run_reproject(const ReprojectOptions& options);

}  // namespace frameless::bench
