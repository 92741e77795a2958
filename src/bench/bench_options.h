// Options shared by several commands and benchmarks, without their flags (tools/tool_options.h
// declares those): camera and shadow overrides, size and thread checks, scene loading, errors.
// Main thread only.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/scene/camera.h"
#include "core/scene/scene.h"

namespace frameless::bench {

// --eye/--look/--up x,y,z and --fov DEG; unset values keep the scene's camera.
struct CameraOptions {
  std::vector<float> eye, look, up;
  std::optional<float> fov;
  // Applies the given values to `camera`; false with a one-line message when invalid.
  bool apply(Camera& camera, std::string& error) const;
};

// --shadows soft|hard|area, --shadow-samples N, --transparent-shadows; unset values keep the
// scene's settings.
struct ShadowOptions {
  std::string mode;
  std::optional<int> samples;
  bool transparent = false;
  std::string accel;  // --accel bvh|grid|auto (empty: the scene's setting)
  std::string integrator;  // --integrator whitted|path (empty: the scene's setting)
  // Applies the options to a loaded scene; false with a one-line message when invalid.
  bool apply(Scene& scene, std::string& error) const;
};

// Parses "WxH" (1..16384 each); false with a one-line message otherwise.
bool parse_size(const std::string& text, int& width, int& height, std::string& error,
                const char* flag = "--size");  // `flag` names the option in the error

// The reprojection budget the benchmarks measure beside the unlimited default: 15 % of a core
// keeps the display thread within 25 % during bench engine's continuous move.
inline constexpr float kBenchReprojectBudget = 0.15f;

// Number of hardware threads (at least 1).
int hardware_threads();
// The executor the core's parallel work runs through (core/base/parallel_for.h): up to `threads`
// threads per call (the caller and threads - 1 new ones), taking indices from a shared counter.
ParallelFor thread_parallel_for(int threads);
// Scene loads and set_accel inside this scope build through `executor` (empty: on one thread),
// for benchmarks that report build times; the process's default (every core in the frameless
// command) comes back at its end.
class ScopedBuildExecutor {
 public:
  explicit ScopedBuildExecutor(ParallelFor executor);
  ~ScopedBuildExecutor();
  ScopedBuildExecutor(const ScopedBuildExecutor&) = delete;
  ScopedBuildExecutor& operator=(const ScopedBuildExecutor&) = delete;

 private:
  ParallelFor before_;
};
// Checks a --threads value (0 = all cores, up to 1024); false with a one-line message otherwise.
bool valid_threads(int threads, std::string& error);

// Loads a scene spec (see load_scene), applies the shadow options when given, and prints
// "frameless: <error>" on failure.
std::unique_ptr<Scene> load_scene_or_report(const std::string& spec,
                                            const ShadowOptions* shadows = nullptr);

// "frameless: MESSAGE" on stderr; returns 2 (silent on cluster ranks other than 0: every rank
// parses the same command line, and one line is enough).
int report_error(const std::string& message);
// Loads like load_scene_or_report but hands the one-line error back instead of printing it.
std::unique_ptr<Scene> load_scene_checked(const std::string& spec, const ShadowOptions* shadows,
                                          std::string& error);
// Whether this process is a cluster client (a rank other than 0 under mpirun).
bool quiet_rank();

// True when stderr is a terminal and CI is not set: progress output is shown only then.
bool show_progress();

}  // namespace frameless::bench
