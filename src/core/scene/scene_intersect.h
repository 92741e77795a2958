// Per-ray queries over a scene and the moving objects of a frame (render threads, any thread).
#pragma once
#include "core/geometry/surface.h"
#include "core/scene/dynamic.h"

namespace frameless {

// Closest hit over the static structure and the dynamic objects (frame may be null).
bool scene_intersect(const Scene& scene, const DynamicFrame* frame, const Ray& ray, Hit& hit);
// Adds the frame's moving objects to `hit`, the static scene's closest hit of `ray` (invalid on a
// miss); returns whether anything was hit.
bool merge_dynamic_hit(const DynamicFrame* frame, const Ray& ray, Hit& hit);
// Adds what lies outside the static structure (isosurfaces, the frame's moving objects) to `hit`.
bool merge_nonstatic_hits(const Scene& scene, const DynamicFrame* frame, const Ray& ray, Hit& hit);
// The same, where `known_hit` (when not null) is the static scene's closest hit of `ray`, already
// found (a camera ray's packet): only the isosurfaces and moving objects are then tested.
inline bool scene_intersect(const Scene& scene, const DynamicFrame* frame, const Ray& ray,
                            const Hit* known_hit, Hit& hit) {
  if (!known_hit) return scene_intersect(scene, frame, ray, hit);
  hit = *known_hit;
  return merge_nonstatic_hits(scene, frame, ray, hit);
}
// Any hit over both (shadow rays).
bool scene_occluded(const Scene& scene, const DynamicFrame* frame, const Ray& ray);
// Surface point of a hit from scene_intersect (static or dynamic).
SurfacePoint scene_surface_point(const Scene& scene, const DynamicFrame* frame, const Ray& ray,
                                 const Hit& hit);
}  // namespace frameless
