// Occluder data soft shadows need beyond the primitives: triangle edge adjacency (which edges
// are outlines) and each spline patch's grid of surface points; built on the loading thread.
#include <bit>
#include <unordered_map>

#include "core/geometry/occluders.h"

namespace frameless {

void build_patch_shadow_grid(Geometry& g) {
  const int n = kPatchShadowGrid + 1;
  g.patch_shadow_grid.clear();
  g.patch_shadow_grid.reserve(g.patches.size() * size_t(n) * n);
  for (const PatchSurface& ps : g.patches)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        g.patch_shadow_grid.push_back(
            bezier_eval(ps.patch(), float(x) / kPatchShadowGrid, float(y) / kPatchShadowGrid));
}

void build_triangle_adjacency(Geometry& g) {
  const uint32_t nt = g.num_triangles();
  g.triangle_opposite.assign(nt, UVec3(kInvalidId));
  auto key = [&](uint32_t v) {
    const Vec3 p = g.positions[v] + Vec3(0.0f);  // -0 and +0 are one position
    uint64_t h = std::bit_cast<uint32_t>(p.x);
    h = h * 0x9e3779b97f4a7c15ull ^ std::bit_cast<uint32_t>(p.y);
    h = h * 0x9e3779b97f4a7c15ull ^ std::bit_cast<uint32_t>(p.z);
    return h;
  };
  struct Side {
    uint32_t tri;
    uint8_t edge;
    uint8_t count;
  };
  std::unordered_map<uint64_t, Side> edges;
  edges.reserve(size_t(nt) * 2);
  std::vector<uint64_t> vkey(g.positions.size());
  for (size_t v = 0; v < vkey.size(); ++v) vkey[v] = key(uint32_t(v));
  auto edge_key = [&](uint64_t a, uint64_t b) {
    if (a > b) std::swap(a, b);
    return a * 0xff51afd7ed558ccdull ^ (b + 0x9e3779b97f4a7c15ull + (a << 6) + (a >> 2));
  };
  for (uint32_t t = 0; t < nt; ++t) {
    const UVec3 tri = g.triangles[t];
    for (uint8_t e = 0; e < 3; ++e) {
      const uint32_t a = tri[e], b = tri[(e + 1) % 3];
      if (a >= vkey.size() || b >= vkey.size()) continue;
      const uint64_t k = edge_key(vkey[a], vkey[b]);
      auto [it, fresh] = edges.try_emplace(k, Side{t, e, 1});
      if (fresh) continue;
      Side& s = it->second;
      ++s.count;
      const UVec3 other = g.triangles[s.tri];
      // Same edge by position (hash collisions are checked by comparing the corners).
      const Vec3 pa = g.positions[a], pb = g.positions[b];
      const Vec3 qa = g.positions[other[s.edge]], qb = g.positions[other[(s.edge + 1) % 3]];
      const bool same = (pa == qa && pb == qb) || (pa == qb && pb == qa);
      if (s.count == 2 && same) {
        g.triangle_opposite[t][e] = other[(s.edge + 2) % 3];
        g.triangle_opposite[s.tri][s.edge] = tri[(e + 2) % 3];
      } else {
        // Non-manifold (three or more faces) or a collision: treat both as open edges.
        g.triangle_opposite[t][e] = kInvalidId;
        g.triangle_opposite[s.tri][s.edge] = kInvalidId;
      }
    }
  }
}

}  // namespace frameless
