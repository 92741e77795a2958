// The fused slab test (core/accel/fused_slab.h) is conservative: a box the ray enters in exact
// arithmetic (long double here, 40 bits beyond float) is never culled, on rays far from the
// origin that graze box corners, where the unconservative fused form (no slack) culls some. And
// which rays it applies to.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/accel/fused_slab.h"

namespace frameless {
namespace {

#if defined(__AVX2__)
// Whether the ray enters box slot i of `n` within [tmin, tmax], in long double.
bool enters_exactly(const Bvh8Node& n, int i, const Ray& r) {
  long double tn = r.tmin, tf = r.tmax;
  for (int a = 0; a < 3; ++a) {
    const long double t0 = ((long double)n.bounds[2 * a][i] - r.org[a]) / r.dir[a];
    const long double t1 = ((long double)n.bounds[2 * a + 1][i] - r.org[a]) / r.dir[a];
    tn = std::max(tn, std::min(t0, t1));
    tf = std::min(tf, std::max(t0, t1));
  }
  return tn <= tf;
}

// The fused form without its slack: X = fl(o * inv), Embree's form (fast mode).
FusedSlab without_slack(const BoxRay& b) {
  FusedSlab s = make_fused_slab(b);
  for (int a = 0; a < 3; ++a) {
    s.x_near[a] = _mm256_set1_ps(b.org[a] * b.inv[a]);
    s.x_far[a] = _mm256_set1_ps(b.org[a] * b.inv_far[a]);
  }
  return s;
}

TEST(FusedSlab, NeverCullsABoxTheRayEnters) {
  std::mt19937 rng(20261203);  // fixed: the same rays every run
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), along(0.5f, 2000.0f), exponent(-2.0f, 5.0f);
  int entered = 0, fused_culled = 0, plain_culled = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // An origin up to 1e5 from the scene's origin, a direction with no tiny component.
    const float scale = std::pow(10.0f, exponent(rng));
    Ray ray;
    ray.org = Vec3(unit(rng), unit(rng), unit(rng)) * scale;
    Vec3 d(unit(rng), unit(rng), unit(rng));
    for (int a = 0; a < 3; ++a)
      if (std::fabs(d[a]) < 1e-3f) d[a] = 1e-3f;
    ray.dir = d;
    ray.tmin = 0.0f;
    ray.tmax = std::numeric_limits<float>::infinity();
    ASSERT_TRUE(fused_slab_applies(ray));
    // Eight boxes with a corner at the float nearest a point of the ray, reaching away from the
    // ray or across it: the ray grazes the corner, entering or missing by an ulp.
    alignas(64) Bvh8Node node;
    for (int i = 0; i < kBvhWidth; ++i) {
      const long double t = along(rng);
      for (int a = 0; a < 3; ++a) {
        const float corner = float((long double)ray.org[a] + t * (long double)ray.dir[a]);
        const float extent = std::fabs(corner) * 1e-3f + 1.0f;
        const bool up = (rng() & 1u) != 0;
        node.bounds[2 * a][i] = up ? corner : corner - extent;
        node.bounds[2 * a + 1][i] = up ? corner + extent : corner;
      }
    }
    const BoxRay br = make_box_ray(ray);
    alignas(32) float dist[kBvhWidth];
    const uint32_t fused = fused_children(node, make_fused_slab(br), ray.tmin, ray.tmax * kRobustFar, dist);
    const uint32_t plain = fused_children(node, without_slack(br), ray.tmin, ray.tmax * kRobustFar, dist);
    for (int i = 0; i < kBvhWidth; ++i) {
      if (!enters_exactly(node, i, ray)) continue;
      ++entered;
      fused_culled += !(fused >> i & 1u);
      plain_culled += !(plain >> i & 1u);
    }
  }
  EXPECT_GT(entered, 10000);
  EXPECT_EQ(fused_culled, 0);
  EXPECT_GT(plain_culled, 0);  // the case is hard enough to catch a form without the slack
}

TEST(FusedSlab, AgreesWithTodaysTestAwayFromTheBoundaries) {
  // Boxes a ray clearly enters or clearly misses (by a thousandth of their size) get the same
  // answer and about the same entry distance from both forms.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int trial = 0; trial < 2000; ++trial) {
    Ray ray;
    ray.org = Vec3(unit(rng), unit(rng), unit(rng)) * 10.0f;
    ray.dir = Vec3(unit(rng), unit(rng), unit(rng));
    if (!fused_slab_applies(ray)) continue;
    alignas(64) Bvh8Node node;
    for (int i = 0; i < kBvhWidth; ++i)
      for (int a = 0; a < 3; ++a) {
        const float c = unit(rng) * 10.0f, h = std::fabs(unit(rng)) * 5.0f + 0.01f;
        node.bounds[2 * a][i] = c - h;
        node.bounds[2 * a + 1][i] = c + h;
      }
    const BoxRay br = make_box_ray(ray);
    alignas(32) float d_fused[kBvhWidth], d_today[kBvhWidth];
    const uint32_t fused = fused_children(node, make_fused_slab(br), 0.0f, 1e30f, d_fused);
    const uint32_t today = intersect_children(node, br, 0.0f, 1e30f, d_today);
    for (int i = 0; i < kBvhWidth; ++i) {
      ray.tmax = 1e30f;
      const bool clear = [&] {  // the exact test gives the same answer with the box grown and shrunk
        Bvh8Node grown = node, shrunk = node;
        for (int a = 0; a < 3; ++a) {
          const float m = (node.bounds[2 * a + 1][i] - node.bounds[2 * a][i]) * 1e-3f;
          grown.bounds[2 * a][i] -= m, grown.bounds[2 * a + 1][i] += m;
          shrunk.bounds[2 * a][i] += m, shrunk.bounds[2 * a + 1][i] -= m;
        }
        return enters_exactly(grown, i, ray) == enters_exactly(shrunk, i, ray);
      }();
      if (!clear) continue;
      ASSERT_EQ(fused >> i & 1u, today >> i & 1u) << "trial " << trial << " box " << i;
      if (today >> i & 1u) EXPECT_NEAR(d_fused[i], d_today[i], 1e-4f * (std::fabs(d_today[i]) + 1.0f));
    }
  }
}
#endif

TEST(FusedSlab, AppliesToOrdinaryRaysOnly) {
  Ray ray;
  ray.org = Vec3(1.0f, 2.0f, 3.0f);
  ray.dir = Vec3(0.3f, -0.5f, 0.8f);
  EXPECT_TRUE(fused_slab_applies(ray));
  Ray axis = ray;
  axis.dir = Vec3(0.0f, 0.0f, 1.0f);  // 0 * inf: today's form reads it as inside the slab
  EXPECT_FALSE(fused_slab_applies(axis));
  Ray tiny = ray;
  tiny.dir.y = 0x1p-61f;
  EXPECT_FALSE(fused_slab_applies(tiny));
  Ray huge = ray;
  huge.dir.x = 0x1p21f;
  EXPECT_FALSE(fused_slab_applies(huge));
  Ray far = ray;
  far.org.z = 0x1p61f;
  EXPECT_FALSE(fused_slab_applies(far));
  Ray behind = ray;
  behind.tmin = -1.0f;
  EXPECT_FALSE(fused_slab_applies(behind));
  Ray nan = ray;
  nan.dir.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(fused_slab_applies(nan));
}

}  // namespace
}  // namespace frameless
