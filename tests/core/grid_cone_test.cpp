// The hybrid grid's cone query (visit_cone) on random and clustered scenes: it visits every
// primitive with a point in the cone, prunes, repeats itself little, and reports stopping early.
#include "core/accel/grid_accel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "core/accel/accel.h"

#include "grid_test_util.h"

namespace frameless {
namespace {

using test_util::append;
using test_util::kRays;
using test_util::mixed_scene;
using test_util::TestRng;
using test_util::stadium;
using test_util::uniform_vec;

// Collects visited primitives.
class Collect : public Accel::ConeVisitor {
 public:
  explicit Collect(size_t n, int stop_after = -1) : seen(n, 0), stop_after_(stop_after) {}
  bool leaf(uint32_t first, uint32_t count) override {
    for (uint32_t p = first; p < first + count; ++p) ++seen[p];
    calls += int(count);
    return stop_after_ < 0 || calls < stop_after_;
  }
  std::vector<int> seen;
  int calls = 0;

 private:
  int stop_after_;
};

bool in_cone(const Vec3& p, const Ray& cone, float tan_half) {
  const Vec3 q = p - cone.org;
  const float s = glm::dot(q, cone.dir);
  if (s < 0.0f || s > cone.tmax) return false;
  return glm::length(q - s * cone.dir) <= tan_half * s;
}

// Whether a sample of the primitive's surface lies in the cone (a subset of the truth).
bool samples_in_cone(const Geometry& g, uint32_t prim, const Ray& cone, float tan_half) {
  constexpr int k = 12;
  if (prim < g.num_triangles()) {
    const UVec3 t = g.triangles[prim];
    const Vec3 a = g.positions[t.x], b = g.positions[t.y], c = g.positions[t.z];
    for (int i = 0; i <= k; ++i)
      for (int j = 0; i + j <= k; ++j)
        if (in_cone(a + (b - a) * (float(i) / k) + (c - a) * (float(j) / k), cone, tan_half))
          return true;
    return false;
  }
  const Sphere& s = g.spheres[prim - g.num_triangles()];
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j < 2 * k; ++j) {
      const float th = kPi * float(i) / k, ph = kPi * float(j) / k;
      const Vec3 d{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
      if (in_cone(s.center + s.radius * d, cone, tan_half)) return true;
    }
  return false;
}

TEST(GridAccel, VisitConeFindsEveryPrimitiveInTheCone) {
  Geometry g = stadium(31, 3000);
  append(g, mixed_scene(32, 400));
  for (int threshold : {16, 1 << 30}) {
    GridConfig cfg;
    cfg.bvh_threshold = threshold;
    GridAccel grid;
    grid.build(g, cfg);
    TestRng rng(33);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    size_t inside = 0, visited = 0, calls = 0;
    const int cones = kRays / 2000 + 10;  // 60 in Release
    for (int i = 0; i < cones; ++i) {
      Ray cone;
      cone.org = uniform_vec(rng, -1.5f, 1.5f);
      const Vec3 target = i % 2 ? uniform_vec(rng, 0.2f, 0.3f) : uniform_vec(rng, -1.0f, 1.0f);
      cone.dir = glm::normalize(target - cone.org);
      if (i % 10 == 0) cone.dir = {0, 0, 1};  // axis-parallel
      cone.tmax = i % 3 ? glm::length(target - cone.org) : 4.0f;
      const float tan_half = i % 5 == 0 ? 0.3f * unit(rng) : 0.05f * unit(rng);
      Collect c(g.num_primitives());
      ASSERT_TRUE(grid.visit_cone(cone, tan_half, c));
      for (uint32_t p = 0; p < g.num_primitives(); ++p) {
        visited += c.seen[p] > 0;
        if (!samples_in_cone(g, p, cone, tan_half)) continue;
        ++inside;
        ASSERT_GT(c.seen[p], 0) << "cone " << i << " missed primitive " << p;
      }
      calls += size_t(c.calls);
    }
    EXPECT_GT(inside, size_t(cones) * 40);
    // It prunes (cell BVHs more than lists), and repeats itself less than once a primitive.
    EXPECT_LT(visited, (threshold == 16 ? 3 : 4) * inside);
    EXPECT_LT(calls, 2 * visited);
  }
  // Stopping early is reported.
  GridAccel grid;
  grid.build(g);
  Ray cone;
  cone.org = {0.25f, 0.25f, -1.0f};
  cone.dir = {0, 0, 1};
  cone.tmax = 3.0f;
  Collect stop(g.num_primitives(), 3);
  EXPECT_FALSE(grid.visit_cone(cone, 0.1f, stop));
  EXPECT_EQ(stop.calls, 3);
}

}  // namespace
}  // namespace frameless
