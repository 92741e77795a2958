// "soup:N[:SEED]": N random triangles about one unit across, their centres uniform in a cube
// whose side grows as cbrt(N), so each overlaps its neighbours at any N. The case where a BVH's
// boxes overlap most (issue 30 measures the kernel on it against Embree; spatial splits are for
// it). Not yet finalized.
#include <cmath>
#include <string>

#include "core/base/rng.h"
#include "core/scene/scene_build.h"
#include "core/scenes/builtin_scenes.h"

namespace frameless {

std::unique_ptr<Scene> make_soup(uint64_t count, uint64_t seed) {
  auto s = std::make_unique<Scene>();
  s->name = "soup:" + std::to_string(count) + ":" + std::to_string(seed);
  const uint16_t mat = add_material(*s, diffuse("soup", Vec3(0.72f, 0.66f, 0.55f)));
  Geometry& g = s->geometry;
  g.positions.reserve(3 * count);
  g.triangles.reserve(count);
  g.triangle_material.reserve(count);
  const float side = std::cbrt(float(count));
  Rng rng(seed);
  const auto next_point = [&rng] {  // one draw per line: the order is fixed on every compiler
    const float x = rng.next_float();
    const float y = rng.next_float();
    const float z = rng.next_float();
    return Vec3(x, y, z) - 0.5f;
  };
  for (uint64_t i = 0; i < count; ++i) {
    const Vec3 centre = side * next_point();
    const uint32_t first = uint32_t(g.positions.size());
    for (int k = 0; k < 3; ++k) g.positions.push_back(centre + next_point());
    g.triangles.push_back(UVec3(first, first + 1, first + 2));
    g.triangle_material.push_back(mat);
  }
  frame_random_scene(*s, seed);
  return s;
}

}  // namespace frameless
