// The step between loading and rendering: features analysed, what soft shadows need built, the
// acceleration structure of the settings' kind built, the cut-out test installed.
#include "core/scene/scene_finalize.h"

#include <atomic>
#include <memory>
#include <utility>

#include "core/geometry/occluders.h"
#include "core/scene/scene_analysis.h"
#include "core/scene/texturing.h"

namespace frameless {
namespace {

// The default executor, swapped whole: a load copies the one it finds, so a later set (a
// benchmark's scope) never changes an executor while a build runs through it.
std::atomic<std::shared_ptr<const ParallelFor>>& executor_slot() {
  static std::atomic<std::shared_ptr<const ParallelFor>> slot;
  return slot;
}

// Builds the structure the settings ask for. The grid has no cut-out test, so scenes with alpha
// cut-outs keep the BVH. Auto gets the scene's own trial: camera rays and shadow rays.
void build_accel(Scene& scene, const AccelConfig& base) {
  AccelConfig config = base;
  if (!config.parallel_for) config.parallel_for = default_build_executor();
  config.kind = scene.features.has_cutouts ? AccelKind::kBvh : scene.settings.accel;
  if (config.kind == AccelKind::kAuto) {
    constexpr int kW = 64, kH = 48;
    const CameraBasis b = make_camera_basis(scene.camera, kW, kH);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) config.trial_rays.push_back(camera_ray(b, x + 0.5f, y + 0.5f));
    for (const Light& l : scene.lights)
      if (l.kind == LightKind::kPoint) config.trial_lights.push_back(l.position);
  }
  scene.accel.build(scene.geometry, config);
  // The path tracer's area lights, in the triangle order the build left (none without emitters).
  scene.emitters = scene.features.has_emission ? build_emitter_table(scene) : EmitterTable{};
}

}  // namespace

void set_default_build_executor(ParallelFor executor) {
  executor_slot().store(executor ? std::make_shared<const ParallelFor>(std::move(executor)) : nullptr);
}

ParallelFor default_build_executor() {
  const std::shared_ptr<const ParallelFor> pf = executor_slot().load();
  return pf ? *pf : ParallelFor{};
}

void refresh_see_through(Scene& scene) {
  scene.see_through_volumes = false;
  for (const VolumeObject& v : scene.volumes) scene.see_through_volumes |= v.mode != VolumeMode::kIsosurface;
  scene.see_through = scene.see_through_volumes || !scene.lightfields.empty();
}

void finalize_scene(Scene& scene, const AccelConfig& config) {
  static std::atomic<uint64_t> next_serial{1};
  scene.serial = next_serial.fetch_add(1, std::memory_order_relaxed);
  scene.features = analyse_scene(scene);
  refresh_see_through(scene);
  // Light that bounces by default only where something emits (the scene's own choice wins).
  if (scene.settings.integrator == Integrator::kAuto)
    scene.settings.integrator = scene.features.has_emission ? Integrator::kPath : Integrator::kWhitted;
  // Edge adjacency only where soft shadows will read it (skip what a scene doesn't need); it is
  // built before the accel so the build permutes it with the triangles.
  if (scene.features.has_soft_lights && scene.geometry.num_triangles() > 0) {
    if (scene.geometry.triangle_opposite.size() != scene.geometry.triangles.size())
      build_triangle_adjacency(scene.geometry);
  } else {
    scene.geometry.triangle_opposite = {};
  }
  build_accel(scene, config);
  // Patch shadow grids follow the patches' order, which the build may permute.
  if (scene.features.has_soft_lights && scene.geometry.num_patches() > 0)
    build_patch_shadow_grid(scene.geometry);
  else
    scene.geometry.patch_shadow_grid = {};
  install_alpha_test(scene);
}

void set_accel(Scene& scene, AccelKind kind, const AccelConfig& config) {
  if (scene.settings.accel == kind && scene.accel.stats().structure == kind) return;
  scene.settings.accel = kind;
  build_accel(scene, config);
  if (!scene.geometry.patch_shadow_grid.empty()) build_patch_shadow_grid(scene.geometry);
  install_alpha_test(scene);
}

void set_shadow_settings(Scene& scene, ShadowMode mode, int samples, bool transparent) {
  scene.settings.shadows = mode;
  scene.settings.shadow_samples = samples;
  scene.settings.transparent_shadows = transparent;
  scene.features = analyse_scene(scene);
  // Adjacency is per triangle in the BVH's current order, so it can be built after the build.
  if (scene.features.has_soft_lights &&
      scene.geometry.triangle_opposite.size() != scene.geometry.triangles.size())
    build_triangle_adjacency(scene.geometry);
  if (scene.features.has_soft_lights && scene.geometry.patch_shadow_grid.empty() &&
      scene.geometry.num_patches() > 0)
    build_patch_shadow_grid(scene.geometry);
}

}  // namespace frameless
