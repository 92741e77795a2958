// Random triangle and sphere soups for the acceleration-structure tests.
#pragma once
#include <random>

#include "core/geometry/geometry.h"

namespace frameless {

using TestRng = std::mt19937;

inline Vec3 uniform_vec(TestRng& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  return {d(rng), d(rng), d(rng)};
}

inline void add_triangle(Geometry& g, Vec3 a, Vec3 b, Vec3 c) {
  const uint32_t i = uint32_t(g.positions.size());
  g.positions.insert(g.positions.end(), {a, b, c});
  g.triangles.push_back({i, i + 1, i + 2});
  g.triangle_material.push_back(uint16_t(g.triangles.size() - 1));
}

inline void add_sphere(Geometry& g, Vec3 c, float r) {
  g.spheres.push_back({c, r});
  g.sphere_material.push_back(uint16_t(g.spheres.size() - 1));
}

inline Geometry random_triangles(uint32_t seed, int n, bool degenerate) {
  TestRng rng(seed);
  Geometry g;
  std::uniform_real_distribution<float> size(0.02f, 0.5f);
  for (int i = 0; i < n; ++i) {
    const Vec3 c = uniform_vec(rng, -1.0f, 1.0f);
    const float s = size(rng);
    Vec3 a = c + s * uniform_vec(rng, -1, 1), b = c + s * uniform_vec(rng, -1, 1),
         d = c + s * uniform_vec(rng, -1, 1);
    if (degenerate && i % 5 == 0) d = a + 0.5f * (b - a);  // collinear: zero area
    if (degenerate && i % 7 == 0) b = d = a;               // a point
    add_triangle(g, a, b, d);
  }
  return g;
}

inline Geometry random_spheres(uint32_t seed, int n) {
  TestRng rng(seed);
  Geometry g;
  std::uniform_real_distribution<float> radius(0.01f, 0.3f);
  for (int i = 0; i < n; ++i) add_sphere(g, uniform_vec(rng, -1.0f, 1.0f), radius(rng));
  return g;
}

inline Geometry mixed_scene(uint32_t seed, int n) {
  Geometry g = random_triangles(seed, n / 2, true);
  const Geometry s = random_spheres(seed + 1, n / 2);
  g.spheres = s.spheres;
  g.sphere_material = s.sphere_material;
  // Some primitives share a centroid exactly (the builder's median fallback).
  for (int i = 0; i < 8; ++i) {
    add_sphere(g, {0.5f, 0.5f, 0.5f}, 0.05f * float(i + 1));
    add_triangle(g, {0.4f, 0.5f, 0.5f}, {0.6f, 0.5f, 0.5f}, {0.5f, 0.5f + 0.01f * float(i), 0.5f});
  }
  return g;
}

}  // namespace frameless
