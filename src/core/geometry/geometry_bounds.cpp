// Bounds of a Geometry's primitives (framing cameras, instance meshes, the auto choice's trial).
#include "core/geometry/geometry.h"

namespace frameless {

bool geometry_bounds(const Geometry& g, Vec3& lo, Vec3& hi) {
  lo = Vec3(kInfinity);
  hi = Vec3(-kInfinity);
  for (const UVec3& t : g.triangles)
    for (int k = 0; k < 3; ++k) {
      lo = glm::min(lo, g.positions[t[k]]);
      hi = glm::max(hi, g.positions[t[k]]);
    }
  for (const Sphere& s : g.spheres) {
    lo = glm::min(lo, s.center - Vec3(s.radius));
    hi = glm::max(hi, s.center + Vec3(s.radius));
  }
  for (const PatchSurface& p : g.patches) {
    lo = glm::min(lo, p.lo());
    hi = glm::max(hi, p.hi());
  }
  return g.num_primitives() > 0;
}

}  // namespace frameless
