// The emissive triangles of a scene as area lights: a table built at finalize time that the
// path tracer samples by power; read-only while rendering (any thread).
#pragma once
#include <cstdint>
#include <vector>

#include "core/base/types.h"

namespace frameless {

struct Scene;

// Static triangles whose material emits, each chosen with probability proportional to its power
// (area times the mean of its material's emission; textures are not looked at, so a textured
// emitter is chosen by its constant emission). Emitters elsewhere (spheres, patches, instances,
// moving objects) are not in the table: paths still see them where they hit them.
struct EmitterTable {
  std::vector<uint32_t> prims;  // triangle ids, ascending
  std::vector<float> cdf;       // cdf[i] = P(index <= i); cdf.back() == 1
  std::vector<float> area;      // area of each triangle
  bool empty() const { return prims.empty(); }
  // Index of the triangle a uniform number u in [0, 1) picks.
  uint32_t pick(float u) const;
  // Probability that pick chooses index i when u is a multiple of 2^-24 (Rng::next_float):
  // the grid points in [cdf[i-1], cdf[i]); 0 for an entry too thin to hold one.
  float pmf(uint32_t i) const;
  // Index of triangle `prim` in the table, or kInvalidId when it is not an emitter.
  uint32_t find(uint32_t prim) const;
};

// A point uniformly distributed over triangle `prim` from (u1, u2) in [0, 1)^2: the point, the
// triangle's unit geometric normal (its winding's) and the barycentrics of vertices 1 and 2 (a
// Hit's u, v), with which the light samplers and the light paths start alike.
struct TrianglePoint {
  Vec3 p{0.0f}, n{0.0f};
  float u = 0.0f, v = 0.0f;
  float scale = 0.0f;  // largest vertex coordinate magnitude (as SurfacePoint::scale)
};
TrianglePoint triangle_point(const Scene& scene, uint32_t prim, float u1, float u2);

// The table for the scene's current geometry and materials (call after the accel build, which
// permutes triangles).
EmitterTable build_emitter_table(const Scene& scene);

}  // namespace frameless
