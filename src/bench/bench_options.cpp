// Options shared by commands and benchmarks: see bench_options.h.
#include "bench/bench_options.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "frameless/thread_executor.h"

namespace frameless::bench {

bool CameraOptions::apply(Camera& camera, std::string& error) const {
  Camera c = camera;
  if (eye.size() == 3) c.eye = Vec3(eye[0], eye[1], eye[2]);
  if (look.size() == 3) c.look = Vec3(look[0], look[1], look[2]);
  if (up.size() == 3) c.up = Vec3(up[0], up[1], up[2]);
  if (fov) c.fov_deg = *fov;
  if (!camera_is_valid(c)) {
    error = "camera flags: invalid camera (need finite values, eye != look, up not parallel to "
            "the view direction, 0 < fov < 180)";
    return false;
  }
  camera = c;
  return true;
}

bool ShadowOptions::apply(Scene& scene, std::string& error) const {
  ShadowMode m = scene.settings.shadows;
  if (mode == "soft") m = ShadowMode::kSoft;
  else if (mode == "hard") m = ShadowMode::kHard;
  else if (mode == "area") m = ShadowMode::kArea;
  else if (mode == "beam") m = ShadowMode::kBeam;
  else if (!mode.empty()) {
    error = "--shadows: expected soft, hard, area or beam, got '" + mode + "'";
    return false;
  }
  int n = scene.settings.shadow_samples;
  if (samples) {
    if (*samples < 1 || *samples > 4096) {
      error = "--shadow-samples: must be 1..4096, got " + std::to_string(*samples);
      return false;
    }
    n = *samples;
  }
  if (!integrator.empty() && !parse_integrator(integrator, scene.settings.integrator)) {
    error = "--integrator: expected whitted, path or igi, got '" + integrator + "'";
    return false;
  }
  set_shadow_settings(scene, m, n, transparent || scene.settings.transparent_shadows);
  if (!accel.empty()) {
    AccelKind kind;
    if (!parse_accel_kind(accel, kind)) {
      error = "--accel: expected bvh, grid or auto, got '" + accel + "'";
      return false;
    }
    set_accel(scene, kind);
    const AccelStats& st = scene.accel.stats();
    if (st.trial)  // auto reports what it chose and why
      std::fprintf(stderr,
                   "frameless: --accel auto chose %s (weighted work on %zu trial rays: bvh %.0f, "
                   "grid %.0f)\n",
                   accel_kind_name(st.structure), st.trial_rays, st.bvh_cost, st.grid_cost);
  }
  return true;
}

bool parse_size(const std::string& text, int& width, int& height, std::string& error, const char* flag) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) {
    error = std::string(flag) + ": expected WxH (e.g. 640x480), got '" + text + "'";
    return false;
  }
  if (w < 1 || h < 1 || w > 16384 || h > 16384) {
    error = std::string(flag) + ": " + text + " is out of range (each side 1..16384)";
    return false;
  }
  width = w, height = h;
  return true;
}

ParallelFor thread_parallel_for(int threads) { return thread_executor(std::max(threads, 1)); }

ScopedBuildExecutor::ScopedBuildExecutor(ParallelFor executor) : before_(default_build_executor()) {
  set_default_build_executor(std::move(executor));
}
ScopedBuildExecutor::~ScopedBuildExecutor() { set_default_build_executor(std::move(before_)); }

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n ? int(n) : 1;
}

bool valid_threads(int threads, std::string& error) {
  if (threads >= 0 && threads <= 1024) return true;
  error = "--threads: must be 0 (all cores) to 1024, got " + std::to_string(threads);
  return false;
}

std::unique_ptr<Scene> load_scene_checked(const std::string& spec, const ShadowOptions* shadows,
                                          std::string& error) {
  auto result = load_scene(spec);
  if (!result.ok()) {
    error = result.error().message;
    return nullptr;
  }
  if (shadows && !shadows->apply(*result.value(), error)) return nullptr;
  return std::move(result.value());
}

std::unique_ptr<Scene> load_scene_or_report(const std::string& spec, const ShadowOptions* shadows) {
  std::string error;
  std::unique_ptr<Scene> scene = load_scene_checked(spec, shadows, error);
  if (!scene) report_error(error);
  return scene;
}

bool quiet_rank() {
  const char* r = std::getenv("OMPI_COMM_WORLD_RANK");
  return r && *r && std::atoi(r) != 0;
}

int report_error(const std::string& message) {
  if (!quiet_rank()) std::fprintf(stderr, "frameless: %s\n", message.c_str());
  return 2;
}

bool show_progress() {
  const char* ci = std::getenv("CI");
  return isatty(STDERR_FILENO) && !(ci && *ci);
}

}  // namespace frameless::bench
