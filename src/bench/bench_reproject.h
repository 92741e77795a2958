// `frameless bench reproject`: the display thread's reprojection (display/reproject.h) alone, on
// one core with nothing else running: a scene's primary hits at every pixel, moved to an orbiting
// camera change after change, in the engine's slot order (how the display keeps its image) and in
// plain pixel order (what that order costs). Its flags are in tools/bench_reproject_command.cpp.
#pragma once
#include <string>

namespace frameless::bench {

struct ReprojectOptions {
  std::string scene = "default";
  std::string size = "1280x720";
  int threads = 2;           // render threads whose slot order the image is kept in
  double degrees = 0.5;      // orbit per camera change (15 degrees a second at 30 Hz)
  int changes = 30;          // timed reprojections per order; the median is reported
  std::string order = "both";  // "slots", "pixels" or both
  bool json = false;
};

int run_reproject(const ReprojectOptions& options);

}  // namespace frameless::bench
