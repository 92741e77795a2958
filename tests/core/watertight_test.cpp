// Watertightness: rays aimed exactly at shared edges and vertices of closed meshes never pass
// through, at the origin and far from it (triangle test and BVH box test together).
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>

#include "core/accel/accel.h"

namespace frameless {
namespace {

// Icosahedron subdivided `levels` times and projected to a sphere of `radius` around `center`;
// vertices are shared so the mesh is closed.
Geometry icosphere(int levels, Vec3 center, float radius) {
  const float p = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<Vec3> v = {{-1, p, 0},  {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                         {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  std::vector<UVec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                          {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                          {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                          {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3& x : v) x = glm::normalize(x);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = uint32_t(v.size() - 1);
    };
    std::vector<UVec3> next;
    for (const UVec3& t : f) {
      const uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
      next.insert(next.end(), {{t.x, ab, ca}, {t.y, bc, ab}, {t.z, ca, bc}, {ab, bc, ca}});
    }
    f.swap(next);
  }
  Geometry g;
  for (const Vec3& x : v) g.positions.push_back(center + radius * x);
  g.triangles = f;
  g.triangle_material.assign(f.size(), 0);
  return g;
}

// Counts rays from `from` aimed exactly at every vertex and every edge's float midpoint that
// escape the closed mesh (they must all hit, in both queries).
int count_leaks(const Geometry& g, const Accel& accel, Vec3 from) {
  int leaks = 0;
  auto shoot = [&](Vec3 target) {
    Ray r;
    r.org = from;
    r.dir = target - from;
    if (glm::dot(r.dir, r.dir) == 0.0f) return;
    Hit h;
    leaks += !accel.intersect(r, h);
    leaks += !accel.occluded(r);
  };
  for (const Vec3& p : g.positions) shoot(p);
  for (const UVec3& t : g.triangles)
    for (int k = 0; k < 3; ++k) shoot(0.5f * (g.positions[t[k]] + g.positions[t[(k + 1) % 3]]));
  return leaks;
}

void expect_watertight(Vec3 center, float radius) {
  Geometry g = icosphere(3, center, radius);
  Accel accel;
  accel.build(g);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> d(-0.5f, 0.5f);
  // From inside: the centre and random interior points.
  EXPECT_EQ(count_leaks(g, accel, center), 0);
  for (int i = 0; i < 4; ++i) {
    const Vec3 o = center + radius * Vec3(d(rng), d(rng), d(rng));
    EXPECT_EQ(count_leaks(g, accel, o), 0) << "interior origin " << i;
  }
}

TEST(Watertight, IcosphereAtOrigin) { expect_watertight({0, 0, 0}, 1.0f); }

TEST(Watertight, IcosphereFarFromOrigin) { expect_watertight({1e5f, -3e4f, 2e5f}, 10.0f); }

TEST(Watertight, TinyIcosphere) { expect_watertight({0.3f, 0.1f, -0.2f}, 1e-3f); }

TEST(Watertight, RaysThroughQuadDiagonalsOfACube) {
  // Unit cube of 12 triangles; each face is split along its diagonal. Axis-parallel rays that
  // hit exactly on that diagonal, on face edges and on corners must hit the cube.
  Geometry g;
  for (int i = 0; i < 8; ++i)
    g.positions.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
  const uint32_t quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : quads) {
    g.triangles.push_back({q[0], q[1], q[2]});
    g.triangles.push_back({q[0], q[2], q[3]});
  }
  g.triangle_material.assign(g.triangles.size(), 0);
  Accel accel;
  accel.build(g);
  int leaks = 0, rays = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (float s : {-1.0f, 1.0f})
      for (int i = 0; i <= 16; ++i)
        for (int j = 0; j <= 16; ++j) {
          // Grid over the face including its edges; diagonal points have i == j or i + j == 16.
          Ray r;
          r.org[axis] = -5.0f * s;
          r.org[(axis + 1) % 3] = -1.0f + float(i) / 8.0f;
          r.org[(axis + 2) % 3] = -1.0f + float(j) / 8.0f;
          r.dir = Vec3(0.0f);
          r.dir[axis] = s;
          Hit h;
          ++rays;
          leaks += !accel.intersect(r, h);
          leaks += !accel.occluded(r);
        }
  EXPECT_EQ(leaks, 0) << "of " << rays << " rays";
}

}  // namespace
}  // namespace frameless
