// OpenRT's volume shader (seed 002, figure 1b) as emission-absorption ray marching over a grid,
// its transmittance for shadow rays, and maximum intensity projection. In grid index space;
// samples every `step` voxels along the ray at a fixed phase (each sample weighted by the part of
// its stretch inside the segment, so any segment is covered exactly), so that skipping the macrocells
// whose values are all transparent leaves every image unchanged. Any thread.
#pragma once
#include <vector>

#include "core/volume/macrocells.h"
#include "core/volume/transfer_function.h"

namespace frameless {

// What a stretch of volume does to the light behind it: adds `color` (already weighted by how
// much of it reaches the eye) and lets `transmittance` of the rest through.
struct VolumeSegment {
  Vec3 color{0.0f};
  float transmittance = 1.0f;
  uint32_t samples = 0;  // samples taken (the benchmarks count them)
};

// The transfer function's largest opacity in each macrocell (0: nothing to see there).
std::vector<float> macrocell_opacity(const Macrocells& cells, const TransferFunction& tf);

// The shading of a sample: its colour's multiplier from the point and the interpolant's
// gradient (index space); null: unlit (emission only).
struct SampleLighting {
  virtual ~SampleLighting() = default;
  virtual Vec3 light(const Vec3& p, const Vec3& gradient) const = 0;
};

inline constexpr int kThinStretches = 4;

struct MarchSetup {
  const VolumeGrid* grid = nullptr;
  const Macrocells* cells = nullptr;
  const std::vector<float>* cell_opacity = nullptr;  // macrocell_opacity(); null: no skipping
  const TransferFunction* tf = nullptr;
  float step = 0.5f;  // voxels between samples (1 / sampling rate)
  const std::vector<float>* step_opacity = nullptr;  // tf->step_opacity(step); null: per sample
  // Adaptive sampling: in macrocells whose largest opacity per voxel is below this, one sample
  // stands for up to kThinStretches stretches (0: off). A chosen bias, measured by bench volume.
  float thin_below = 0.0f;
};

// Front-to-back compositing over org + t dir, t in [t0, t1]: each sample's opacity a becomes
// 1 - (1 - a)^step (the transfer function's opacity is per voxel); stops once less than 1e-3
// of the light gets through (early ray termination).
VolumeSegment march_volume(const MarchSetup& s, const Vec3& org, const Vec3& dir, float t0, float t1,
                           const SampleLighting* lighting);
// The product of (1 - a) over the same samples, per channel tinted by each sample's colour
// (shadow_tint): what a shadow ray keeps; 0 in channels below 1e-3.
Vec3 march_transmittance(const MarchSetup& s, const Vec3& org, const Vec3& dir, float t0, float t1);
// The largest interpolated value over the samples (maximum intensity projection); false when no
// sample lies in [t0, t1].
bool march_maximum(const MarchSetup& s, const Vec3& org, const Vec3& dir, float t0, float t1, float& value,
                   uint32_t* samples = nullptr);

}  // namespace frameless
