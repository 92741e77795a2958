// `frameless bench motion --sweep`: the motion benchmark over a range of regimes (a conventional
// frame's time against the camera input interval, from below 1 to 5 and more), by image size and
// scene, with the error of each frameless setting against double buffering plotted against it.
#pragma once
#include <string>
#include <vector>

#include "bench/bench_motion.h"

namespace frameless::bench {

struct MotionSweepOptions {
  MotionOptions base;  // every run's settings but scene and size; base.out holds the sweep
  std::vector<std::string> scenes = {"default", "bunny"};
  std::vector<std::string> sizes = {"160x120", "320x240", "640x360", "960x540"};
};

// Runs bench motion once per (scene, size) into OUT/SCENE_SIZE, then writes OUT/sweep.json,
// sweep.csv and sweep.png; returns the exit code (2 after a one-line error on stderr).
int run_motion_sweep(const MotionSweepOptions& options);

}  // namespace frameless::bench
