// Textures applied at hits: texture coordinates of a hit, textured material parameters and
// perturbed shading normals, and the alpha cut-out test the traversal calls. Pure, any thread.
#pragma once
#include "core/geometry/surface.h"
#include "core/scene/scene.h"

namespace frameless {

// Texture coordinates at a hit: interpolated vertex UVs (or the barycentrics when the mesh has
// none), the spherical map (u around the y axis, v from the south pole) for spheres.
Vec2 hit_uv(const Geometry& geom, const Ray& ray, const Hit& hit);

// Tangent frame of a hit's UV parameterisation: dp/du (not yet orthogonal to the normal) and its
// handedness, -1 where the UVs are mirrored so that dp/dv runs against n x dp/du. Primitives
// without UVs get a tangent in their plane (spheres: eastward).
struct UvTangent {
  Vec3 dpdu{1.0f, 0.0f, 0.0f};
  float handedness = 1.0f;
};
UvTangent uv_tangent(const Geometry& g, const Hit& hit, const SurfacePoint& sp);

// Multiplies the textured colours into m and perturbs sp.ns by the normal or bump map.
void apply_textures(const Scene& scene, const Ray& ray, const Hit& hit, MaterialParams& m,
                    SurfacePoint& sp);
// The same on geometry g (a shared mesh's, with an object-space ray and hit).
void apply_textures(const Scene& scene, const Geometry& g, const Ray& ray, const Hit& hit,
                    MaterialParams& m, SurfacePoint& sp);

// Whether a hit (t, barycentrics u, v) on primitive prim is on an opaque part of its surface.
bool cutout_opaque(const Scene& scene, uint32_t prim, const Ray& ray, float t, float u, float v);

// Installs the cut-out test in the scene's accel when some material has one (finalize_scene).
void install_alpha_test(Scene& scene);

}  // namespace frameless
