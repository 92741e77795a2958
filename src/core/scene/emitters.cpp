// Emissive triangles chosen by power (the path tracer's area lights).
#include "core/scene/emitters.h"

#include <algorithm>
#include <cmath>

#include "core/scene/scene.h"

namespace frameless {

uint32_t EmitterTable::pick(float u) const {
  const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
  return uint32_t(std::min<size_t>(size_t(it - cdf.begin()), cdf.size() - 1));
}

float EmitterTable::pmf(uint32_t i) const {
  const double lo = i == 0 ? 0.0 : std::ceil(double(cdf[i - 1]) * 0x1.0p24);
  return float((std::ceil(double(cdf[i]) * 0x1.0p24) - lo) * 0x1.0p-24);
}

uint32_t EmitterTable::find(uint32_t prim) const {
  const auto it = std::lower_bound(prims.begin(), prims.end(), prim);
  return it != prims.end() && *it == prim ? uint32_t(it - prims.begin()) : kInvalidId;
}

TrianglePoint triangle_point(const Scene& scene, uint32_t prim, float u1, float u2) {
  const Geometry& g = scene.geometry;
  const UVec3 tri = g.triangles[prim];
  const Vec3 a = g.positions[tri.x], b = g.positions[tri.y], c = g.positions[tri.z];
  TrianglePoint t;
  const float su = std::sqrt(u1);
  t.u = u2 * su;
  t.v = 1.0f - su;
  t.p = a + t.u * (b - a) + t.v * (c - a);
  t.n = glm::normalize(glm::cross(b - a, c - a));
  const Vec3 m = glm::max(glm::abs(a), glm::max(glm::abs(b), glm::abs(c)));
  t.scale = std::max(m.x, std::max(m.y, m.z));
  return t;
}

EmitterTable build_emitter_table(const Scene& scene) {
  EmitterTable t;
  const Geometry& g = scene.geometry;
  std::vector<double> power;
  for (uint32_t i = 0; i < g.num_triangles(); ++i) {
    const uint16_t mat = i < g.triangle_material.size() ? g.triangle_material[i] : 0;
    if (mat >= scene.materials.size()) continue;
    const Vec3 e = scene.materials[mat].emission;
    const double mean = (double(e.x) + e.y + e.z) / 3.0;
    if (!(mean > 0.0)) continue;
    const UVec3 tri = g.triangles[i];
    const Vec3 a = g.positions[tri.x], b = g.positions[tri.y], c = g.positions[tri.z];
    const float area = 0.5f * glm::length(glm::cross(b - a, c - a));
    if (!(area > 0.0f) || !std::isfinite(area)) continue;
    t.prims.push_back(i);
    t.area.push_back(area);
    power.push_back(mean * area);
  }
  double total = 0.0;
  for (double p : power) total += p;
  double run = 0.0;
  for (double p : power) {
    run += p;
    t.cdf.push_back(float(run / total));
  }
  if (!t.cdf.empty()) t.cdf.back() = 1.0f;
  return t;
}

}  // namespace frameless
