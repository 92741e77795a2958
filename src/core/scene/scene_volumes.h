// Per-ray queries over a scene's volumes (core/scene/volume_object.h): isosurface hits and their
// surface points, and what the volume shader and MIP volumes do to light along a ray or a shadow
// ray. Render threads, any thread.
#pragma once
#include "core/geometry/surface.h"
#include "core/scene/scene.h"

namespace frameless {

// Lowers `hit` to the nearest isosurface hit of `ray` before it (or before ray.tmax when hit is
// invalid); returns whether anything is hit now.
bool merge_volume_hits(const Scene& scene, const Ray& ray, Hit& hit);
// Whether an isosurface blocks `ray` within [tmin, tmax].
bool volumes_occlude(const Scene& scene, const Ray& ray);
// The surface point of an isosurface hit: normal from the interpolant's gradient, pointing out of
// the inside (values above the isovalue unless the volume says below).
SurfacePoint volume_surface_point(const Scene& scene, const Ray& ray, const Hit& hit);

// How the shading layer lights a volume-shader sample: a multiplier of its colour from its world
// position and unit normal (zero where the gradient vanishes).
struct VolumeLighting {
  virtual ~VolumeLighting() = default;
  virtual Vec3 light(const Vec3& p, const Vec3& n) const = 0;
};

// The light the scene's volume-shader and MIP volumes add along ray [tmin, t_end] and the share
// of what lies behind that passes; `lighting` shades volume-shader samples (null: unlit).
VolumeSegment volumes_along(const Scene& scene, const Ray& ray, float t_end, const VolumeLighting* lighting);
// What a shadow ray [tmin, tmax] keeps through the volume-shader volumes (MIP volumes cast none).
Vec3 volumes_transmittance(const Scene& scene, const Ray& ray);
// Whether the scene has volumes that light passes through (volume shader or MIP).
inline bool has_see_through_volumes(const Scene& scene) { return scene.see_through_volumes; }

}  // namespace frameless
