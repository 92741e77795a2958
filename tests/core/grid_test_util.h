// Random and structured triangle and sphere scenes (material 0) for the grid accelerator tests.
#pragma once
#include <cstdint>
#include <random>

#include "core/geometry/geometry.h"

#include "slow_build.h"

namespace frameless {
namespace test_util {

// Rays per comparison: fewer under sanitizers.
#if defined(FRAMELESS_SLOW_BUILD)
inline constexpr int kRays = 10000;
#else
inline constexpr int kRays = 100000;
#endif

using TestRng = std::mt19937;

inline Vec3 uniform_vec(TestRng& rng, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  return {d(rng), d(rng), d(rng)};
}

inline void add_triangle(Geometry& g, Vec3 a, Vec3 b, Vec3 c) {
  const uint32_t i = uint32_t(g.positions.size());
  g.positions.insert(g.positions.end(), {a, b, c});
  g.triangles.push_back({i, i + 1, i + 2});
  g.triangle_material.push_back(0);
}

inline void add_sphere(Geometry& g, Vec3 c, float r) {
  g.spheres.push_back({c, r});
  g.sphere_material.push_back(0);
}

inline Geometry random_triangles(uint32_t seed, int n, bool degenerate, float max_size = 0.5f) {
  TestRng rng(seed);
  Geometry g;
  std::uniform_real_distribution<float> size(0.02f, max_size);
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

inline Geometry random_spheres(uint32_t seed, int n, float max_radius = 0.3f) {
  TestRng rng(seed);
  Geometry g;
  std::uniform_real_distribution<float> radius(0.01f, max_radius);
  for (int i = 0; i < n; ++i) add_sphere(g, uniform_vec(rng, -1.0f, 1.0f), radius(rng));
  return g;
}

inline void append(Geometry& g, const Geometry& more) {
  const uint32_t base = uint32_t(g.positions.size());
  g.positions.insert(g.positions.end(), more.positions.begin(), more.positions.end());
  for (UVec3 t : more.triangles) g.triangles.push_back(t + UVec3(base));
  g.triangle_material.resize(g.triangles.size(), 0);
  g.spheres.insert(g.spheres.end(), more.spheres.begin(), more.spheres.end());
  g.sphere_material.resize(g.spheres.size(), 0);
}

inline Geometry mixed_scene(uint32_t seed, int n) {
  Geometry g = random_triangles(seed, n / 2, true);
  append(g, random_spheres(seed + 1, n / 2));
  // Primitives sharing one point, and grid-aligned planes through the scene.
  for (int i = 0; i < 8; ++i) {
    add_sphere(g, {0.5f, 0.5f, 0.5f}, 0.05f * float(i + 1));
    add_triangle(g, {0.4f, 0.5f, 0.5f}, {0.6f, 0.5f, 0.5f}, {0.5f, 0.5f + 0.01f * float(i), 0.5f});
  }
  add_triangle(g, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1});
  add_triangle(g, {-1, 0, -1}, {1, 0, 1}, {-1, 0, 1});
  return g;
}

// A dense cluster of tiny triangles in a big, sparse scene ("teapot in a stadium").
inline Geometry stadium(uint32_t seed, int cluster) {
  TestRng rng(seed);
  Geometry g;
  for (int i = 0; i < cluster; ++i) {
    const Vec3 c = uniform_vec(rng, 0.2f, 0.3f);
    add_triangle(g, c + uniform_vec(rng, -0.01f, 0.01f), c + uniform_vec(rng, -0.01f, 0.01f),
                 c + uniform_vec(rng, -0.01f, 0.01f));
  }
  add_triangle(g, {-1, -0.5f, -1}, {1, -0.5f, -1}, {1, -0.5f, 1});
  add_triangle(g, {-1, -0.5f, -1}, {1, -0.5f, 1}, {-1, -0.5f, 1});
  add_sphere(g, {-0.5f, 0.5f, -0.5f}, 0.4f);
  add_sphere(g, {0.9f, 0.9f, 0.9f}, 0.05f);
  return g;
}

}  // namespace test_util
}  // namespace frameless
