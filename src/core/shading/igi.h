// OpenRT's instant global illumination (Wald, Kollig, Benthin, Keller and Slusallek 2002) in a
// frameless renderer (docs/global-illumination.md): direct light by next-event estimation,
// indirect light from a set of virtual point lights chosen by interleaved sampling, a fresh set
// for every update of a pixel. Pure per sample; each thread keeps its own cache of VPL sets.
#pragma once
#include "core/geometry/surface.h"
#include "core/scene/dynamic.h"
#include "core/scene/scene.h"

namespace frameless {

// Radiance along `ray` through image position (px, py) for sample `sample_index` of its pixel:
// the pixel's class in the interleave x interleave pattern and the sample index choose the VPL
// set (set = sample_index * interleave^2 + class). `first_indirect` receives the VPLs' light at
// the primary hit (what OpenRT's discontinuity buffer filters). Other arguments as trace_path.
Vec3 trace_igi(const Scene& scene, const Ray& ray, float px, float py, uint32_t sample_index,
               uint64_t seed, const DynamicFrame* frame = nullptr, const Hit* known_hit = nullptr,
               Hit* first_hit = nullptr, SurfacePoint* first_point = nullptr, int* bounces = nullptr,
               Vec3* first_albedo = nullptr, Vec3* first_indirect = nullptr);

}  // namespace frameless
