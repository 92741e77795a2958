// How the volume shader's samples are lit (OpenRT's volume shader is gradient-shaded): the
// scene's ambient at the sample plus each Parker light's l_e |n . l|, two-sided because a
// gradient's sign says nothing of which side the light is on. Samples cast no shadow rays (their
// cost would multiply by the samples per ray); samples where the gradient vanishes are unlit
// (their colour as it is). Render threads, any thread.
#pragma once
#include "core/scene/dynamic.h"
#include "core/scene/scene_volumes.h"

namespace frameless {

class ParkerVolumeLighting final : public VolumeLighting {
 public:
  ParkerVolumeLighting(const Scene& scene, const DynamicFrame* frame) : scene_(scene), frame_(frame) {}
  Vec3 light(const Vec3& p, const Vec3& n) const override;

 private:
  const Scene& scene_;
  const DynamicFrame* frame_;
};

// What lies behind along `ray` up to t_end, seen through the scene's volume-shader and MIP
// volumes and its lightfields, front to back (the colour as it is when the scene has none).
Vec3 through_volumes(const Scene& scene, const DynamicFrame* frame, const Ray& ray, float t_end, const Vec3& behind);

// A path's vertex-to-vertex stretch through them: adds their light times beta to radiance and
// dims beta by their transmittance; false when nothing gets through any more.
bool through_volumes(const Scene& scene, const DynamicFrame* frame, const Ray& ray, float t_end, Vec3& radiance,
                     Vec3& beta);

// A shadow ray's share of light through the volumes: 0 when an isosurface blocks it (with
// `isosurfaces`; the hard-shadow queries already test them), else the volume shader's
// transmittance.
Vec3 volume_shadow(const Scene& scene, const Ray& ray, bool isosurfaces);

// The same over the cone a light subtends (tan of its half-angle): the mean of five rays, the
// centre and four at half the cone's radius, so isosurfaces cast penumbrae under Parker's
// single-sample soft shadows, whose cone query does not see them.
Vec3 volume_cone_shadow(const Scene& scene, const Ray& ray, float tan_half);

}  // namespace frameless
