// The pure per-sample function: camera ray, Whitted shading or a path, NaN/Inf guard.
#include "core/shading/render_sample.h"

#include <algorithm>
#include <cmath>

#include "core/base/rng.h"
#include "core/base/sobol.h"
#include "core/scene/scene_analysis.h"
#include "core/shading/igi.h"
#include "core/shading/path_tracer.h"
#include "core/shading/shading.h"

namespace frameless {

SampleResult trace_sample(const Scene& scene, const CameraBasis& camera, float px, float py,
                          uint64_t rng_seed, const DynamicFrame* frame, const Hit* known_hit,
                          uint32_t sample_index) {
  const Ray ray = camera_ray(camera, px, py);
  SampleResult out;
  Hit hit;
  SurfacePoint sp;
  int levels = 0;
  if (scene.settings.integrator == Integrator::kPath) {
    out.color = trace_path(scene, ray, rng_seed, frame, known_hit, &hit, &sp, &levels, {}, &out.albedo);
  } else if (scene.settings.integrator == Integrator::kIgi) {
    out.color = trace_igi(scene, ray, px, py, sample_index, rng_seed, frame, known_hit, &hit, &sp,
                          &levels, &out.albedo, &out.indirect);
  } else {
    // The shading path is chosen once per sample from the scene's features and skips.
    out.color = trace_radiance_path(scene, frame ? frame->shade_path : shade_path(scene), ray, 0,
                                    Vec3(1.0f), nullptr, &hit, &sp, rng_seed, frame, known_hit,
                                    &levels);
  }
  out.levels = uint8_t(std::min(levels, 255));
  if (hit.valid()) {
    out.depth = hit.t;  // ray.dir is unit, so t is the distance from the eye
    out.normal = sp.ns;
    // Reprojection's point: the hit moved onto the pixel centre's ray at the same view depth, so
    // the points of one view form a grid whatever the jitter (a forward splat then leaves no
    // random holes) and a pixel is moved by its centre's motion.
    // (No normalize: camera_direction's view-axis component is 1.)
    const Vec3 centre = camera_direction(camera, std::floor(px) + 0.5f, std::floor(py) + 0.5f);
    out.position = camera.eye + centre * (glm::dot(ray.dir, camera.w) * hit.t);
    out.object = is_dynamic_prim(hit.prim) ? kPointDynamic + (hit.prim - kDynamicPrimBase)
                 : hit.inst != kInvalidId  ? kPointInstance + (hit.inst & 0x0fffffffu)
                                           : kPointStatic;
  } else {
    out.position = camera_direction(camera, std::floor(px) + 0.5f, std::floor(py) + 0.5f);
    out.object = kPointSky;
  }
  // Drop any sample in which a NaN or Inf arose; the caller counts it.
  out.valid = is_finite(out.color) && is_finite(out.normal) && out.depth == out.depth &&
              (hit.valid() ? out.depth < kInfinity : true);
  if (!out.valid) {
    out.color = Vec3(0.0f);
    out.normal = Vec3(0.0f);
    out.albedo = Vec3(0.0f);
    out.indirect = Vec3(0.0f);
    out.depth = kInfinity;
    out.object = kPointNone;
  }
  return out;
}

void primary_hits(const Scene& scene, const CameraBasis& camera, int n, const float* px,
                  const float* py, Hit* hits, const DynamicFrame* frame) {
  Ray rays[kPacketSize];
  for (int b = 0; b < n; b += kPacketSize) {
    const int m = std::min(kPacketSize, n - b);
    for (int k = 0; k < m; ++k) rays[k] = camera_ray(camera, px[b + k], py[b + k]);
    scene.accel.intersect_packet(rays, m, hits + b, frame_instances(frame));
  }
}

SampleResult render_sample(const Scene& scene, const CameraBasis& camera, int x, int y,
                           uint32_t sample_index, bool jitter, const DynamicFrame* frame) {
  const uint64_t seed = sample_seed(uint32_t(x), uint32_t(y), sample_index, scene.settings.seed);
  float jx = 0.5f, jy = 0.5f;
  if (jitter && scene.settings.integrator >= Integrator::kPath) {
    // Stratified at every power of two of the pixel's samples (Owen-scrambled Sobol').
    owen_sobol_2d(sample_index, sample_seed(uint32_t(x), uint32_t(y), 0, scene.settings.seed ^ 0x50b01ull), jx, jy);
  } else if (jitter) {
    Rng rng(seed);
    jx = rng.next_float();
    jy = rng.next_float();
  }
  // A distinct stream for shading, so jitter and shading choices never share numbers.
  return trace_sample(scene, camera, float(x) + jx, float(y) + jy, mix64(seed ^ 0x5bd1e995ull), frame,
                      nullptr, sample_index);
}

}  // namespace frameless
