// Visibility of a light with an extent from a surface point: Parker, Shirley and Smits'
// single-sample soft shadows (seed section 3.2, Utah tech report UUCS-98-019), the area-sampled
// reference, and shadow rays through dielectrics. Pure functions on a finalized scene, any thread.
#pragma once
#include "core/base/rng.h"
#include "core/scene/dynamic.h"
#include "core/scene/scene.h"

namespace frameless {

// One shadow query: from org toward the light's centre along dir (unit). Occluders count over
// (0, tmax): up to the light's surface, or forever for a directional light. tan_half and
// half_angle describe the cone the light subtends (0 for a point light).
struct ShadowQuery {
  Vec3 org{0.0f};
  Vec3 dir{0.0f, 1.0f, 0.0f};
  float tmax = kInfinity;
  float tan_half = 0.0f;
  float half_angle = 0.0f;
  bool skip_dielectrics = false;  // transparent shadows: dielectrics are handled by transmittance
  uint32_t receiver = kInvalidId;  // primitive the query starts on (a patch shadows itself exactly)
};

// Fraction of a uniformly bright disk left visible by a straight edge at signed distance x
// (in disk radii; x > 0: the edge leaves the centre uncovered): 1 - (acos x - x sqrt(1 - x^2))/pi,
// 0 for x <= -1, 1 for x >= 1. This is the report's "sinusoid" for a straight edge, used exactly.
float edge_visibility(float x);

// Single-sample soft shadow s in [0, 1] for one light: one cone query over the BVH.
float soft_visibility(const Scene& scene, const ShadowQuery& q,
                      const DynamicFrame* frame = nullptr);

// Parker et al.'s beam shadows (section 3.2): four shadow rays in a fixed pattern across the
// light's cone (the same for every point: precomputed for a distant light), traced together as
// one packet; the fraction that gets through (0, 1/4, ... 1). Deterministic, so its penumbrae
// are banded; without moving objects, volumes or transparent shadows the four share one
// traversal (Accel::occluded_packet), else they go ray by ray.
Vec3 beam_visibility(const Scene& scene, const ShadowQuery& q, const DynamicFrame* frame = nullptr);

// Area-sampled reference: `samples` rays spread (stratified) over the cone; the fraction
// unblocked, or with q.skip_dielectrics (transparent shadows) their mean transmittance.
Vec3 area_visibility(const Scene& scene, const ShadowQuery& q, int samples, Rng& rng,
                     const DynamicFrame* frame = nullptr);

// Transmittance along a shadow ray through dielectrics (k_t at each interface, Beer's law
// inside): 0 when an opaque surface blocks it, unless ignore_opaque (soft mode leaves opaque
// occluders to the cone query).
Vec3 shadow_transmittance(const Scene& scene, const Ray& ray, bool ignore_opaque,
                          const DynamicFrame* frame = nullptr);

}  // namespace frameless
