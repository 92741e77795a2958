// The volume shader's marching (core/volume/volume_march.h): Beer's law through a homogeneous
// block, images independent of the sampling rate, macrocell skipping that changes nothing, MIP's
// maximum, and transfer functions' checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/volume/isosurface.h"
#include "core/volume/volume_generators.h"
#include "core/volume/volume_march.h"

namespace frameless {
namespace {

std::shared_ptr<const VolumeGrid> constant_grid(int n, float value) {
  std::vector<float> v(size_t(n) * n * n, value);
  std::vector<uint8_t> bytes(v.size() * 4);
  std::memcpy(bytes.data(), v.data(), bytes.size());
  return *make_volume_grid(n, n, n, VoxelType::kFloat32, Vec3(1.0f), owned_storage(std::move(bytes)), "test");
}

TEST(VolumeMarch, HomogeneousBlockTransmitsExpMinusSigmaD) {
  const auto g = constant_grid(17, 1.0f);
  const Macrocells m = build_macrocells(*g);
  for (float alpha : {0.01f, 0.1f, 0.3f}) {
    auto tf = TransferFunction::make({{0.0f, Vec3(1.0f), alpha}, {2.0f, Vec3(1.0f), alpha}}, "tf");
    ASSERT_TRUE(tf) << tf.error().message;
    const float sigma = -std::log(1.0f - alpha);  // extinction per voxel
    for (float step : {1.0f, 0.5f, 0.125f}) {
      MarchSetup s{g.get(), &m, nullptr, &*tf, step};
      // Straight through along x (16 voxels), and along a diagonal of the z = 8 plane.
      const Vec3 tint = march_transmittance(s, Vec3(-3.0f, 8.0f, 8.0f), Vec3(1, 0, 0), 0.0f, 100.0f);
      EXPECT_TRUE(tint.x == tint.y && tint.y == tint.z) << "a white medium's shadow is grey";
      const float t = tint.x;
      EXPECT_NEAR(t, std::exp(-sigma * 16.0f), 1e-4f + 1e-3f * t) << alpha << " step " << step;
      // The volume shader's own transmittance agrees with the shadow ray's.
      const VolumeSegment seg = march_volume(s, Vec3(-3.0f, 8.0f, 8.0f), Vec3(1, 0, 0), 0.0f, 100.0f, nullptr);
      if (t >= 1e-3f) EXPECT_NEAR(seg.transmittance, t, 1e-5f);
      // Emission-absorption of a white medium: what does not get through is emitted.
      if (t >= 1e-3f) EXPECT_NEAR(seg.color.x, 1.0f - t, 1e-4f);
      // A part of the way: from inside to inside, 5.5 voxels.
      const float part = march_transmittance(s, Vec3(2.0f, 8.0f, 8.0f), Vec3(1, 0, 0), 0.0f, 5.5f).y;
      EXPECT_NEAR(part, std::exp(-sigma * 5.5f), 1e-3f * std::exp(-sigma * 5.5f) + 1e-5f) << alpha << " step " << step;
    }
  }
}

// A coloured medium's shadow takes its colour (docs/volumes.md: shadow_tint) and keeps the grey
// medium's optical depth on average over the channels.
TEST(VolumeMarch, ColouredMediaCastColouredShadows) {
  const auto g = constant_grid(17, 1.0f);
  const Macrocells m = build_macrocells(*g);
  const Vec3 colour(1.0f, 0.5f, 0.2f);
  auto tf = TransferFunction::make({{0.0f, colour, 0.1f}, {2.0f, colour, 0.1f}}, "tf");
  ASSERT_TRUE(tf);
  const MarchSetup s{g.get(), &m, nullptr, &*tf, 0.5f};
  const Vec3 t = march_transmittance(s, Vec3(-3.0f, 8.0f, 8.0f), Vec3(1, 0, 0), 0.0f, 100.0f);
  EXPECT_GT(t.x, t.y);  // red passes most, blue least
  EXPECT_GT(t.y, t.z);
  const float grey_depth = -std::log(0.9f) * 16.0f;
  EXPECT_NEAR(-(std::log(t.x) + std::log(t.y) + std::log(t.z)) / 3.0f, grey_depth, 1e-3f * grey_depth);
  // Weights 1.05 - c = (0.05, 0.55, 0.85) over their mean 1.45 / 3: red keeps 0.15 / 1.45 of the grey depth.
  EXPECT_NEAR(-std::log(t.x), grey_depth * 0.15f / 1.45f, 1e-3f);
}

TEST(VolumeMarch, ImagesDoNotDependOnTheSamplingRate) {
  const auto g = make_marschner_lobb(41);
  const Macrocells m = build_macrocells(*g);
  auto tf = TransferFunction::preset("hot", g->min_value, g->max_value, "tf");
  ASSERT_TRUE(tf);
  const std::vector<float> cell_opacity = macrocell_opacity(m, *tf);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 40.0f);
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 from(u(rng), u(rng), -10.0f), to(u(rng), u(rng), 50.0f);
    const Vec3 d = glm::normalize(to - from);
    Vec3 c[3];
    int k = 0;
    for (float step : {0.5f, 0.25f, 0.125f}) {
      MarchSetup s{g.get(), &m, &cell_opacity, &*tf, step};
      c[k++] = march_volume(s, from, d, 0.0f, 200.0f, nullptr).color;
    }
    // Halving the step converges: the images at 0.25 and 0.125 voxels agree within 2 % of white.
    worst = std::max(worst, double(max_component(glm::abs(c[1] - c[2]))));
  }
  EXPECT_LT(worst, 0.005) << worst;  // half a percent of white
  std::printf("worst difference between steps 0.25 and 0.125: %.4f\n", worst);
}

TEST(VolumeMarch, SkippingTransparentMacrocellsChangesNothing) {
  const auto g = *make_builtin_volume("volume:shepp-logan:64");
  const Macrocells m = build_macrocells(*g);
  auto tf = TransferFunction::preset("ct-bone", g->min_value, g->max_value, "tf");
  ASSERT_TRUE(tf);
  const std::vector<float> cell_opacity = macrocell_opacity(m, *tf);
  size_t transparent = 0;
  for (float o : cell_opacity) transparent += o <= 0.0f;
  EXPECT_GT(transparent, cell_opacity.size() / 10);  // the test has power: air around the head
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-10.0f, 73.0f);
  uint32_t skipped = 0, all = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 from(u(rng), u(rng), -20.0f), to(u(rng), u(rng), 90.0f);
    const Vec3 d = glm::normalize(to - from);
    MarchSetup with{g.get(), &m, &cell_opacity, &*tf, 0.5f}, without{g.get(), &m, nullptr, &*tf, 0.5f};
    const VolumeSegment a = march_volume(with, from, d, 0.0f, 300.0f, nullptr);
    const VolumeSegment b = march_volume(without, from, d, 0.0f, 300.0f, nullptr);
    ASSERT_EQ(a.color, b.color) << i;
    ASSERT_EQ(a.transmittance, b.transmittance) << i;
    skipped += a.samples;
    all += b.samples;
  }
  EXPECT_LT(skipped, all);
}

// Adaptive sampling (MarchSetup::thin_below): in nearly transparent macrocells one sample stands
// for up to four stretches (2 voxels at rate 2). A third of the samples; colour and transmittance
// within 1 % of white of the exact march on the phantom's sharp ellipsoid edges (the bench measures
// an image RMSE of 1e-4 on the large phantom).
TEST(VolumeMarch, AdaptiveSamplingThinsNearlyTransparentCellsWithinTolerance) {
  const auto g = *make_builtin_volume("volume:shepp-logan:64");
  const Macrocells m = build_macrocells(*g);
  auto tf = TransferFunction::preset("ct-skin", g->min_value, g->max_value, "tf");
  ASSERT_TRUE(tf);
  // Low opacity everywhere (2 % of ct-skin's): every macrocell is below the threshold.
  std::vector<TransferPoint> thin = tf->points();
  for (TransferPoint& p : thin) p.opacity *= 0.02f;
  auto faint = TransferFunction::make(thin, "tf");
  ASSERT_TRUE(faint);
  const std::vector<float> cell_opacity = macrocell_opacity(m, *faint);
  std::mt19937 rng(28);
  std::uniform_real_distribution<float> u(-10.0f, 73.0f);
  uint64_t exact_samples = 0, thinned_samples = 0;
  double worst = 0.0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 from(u(rng), u(rng), -20.0f), to(u(rng), u(rng), 90.0f);
    const Vec3 d = glm::normalize(to - from);
    MarchSetup exact{g.get(), &m, &cell_opacity, &*faint, 0.5f};
    MarchSetup thinned = exact;
    thinned.thin_below = 0.02f;  // kAdaptiveOpacity, the scenes' default
    const VolumeSegment a = march_volume(exact, from, d, 0.0f, 300.0f, nullptr);
    const VolumeSegment b = march_volume(thinned, from, d, 0.0f, 300.0f, nullptr);
    worst = std::max(worst, double(max_component(glm::abs(a.color - b.color))));
    worst = std::max(worst, double(std::abs(a.transmittance - b.transmittance)));
    EXPECT_NEAR(march_transmittance(exact, from, d, 0.0f, 300.0f).x, march_transmittance(thinned, from, d, 0.0f, 300.0f).x, 0.01f);
    exact_samples += a.samples;
    thinned_samples += b.samples;
  }
  EXPECT_LT(worst, 0.01) << worst;
  EXPECT_LT(thinned_samples * 3, exact_samples) << thinned_samples << " of " << exact_samples;
  std::printf("adaptive sampling: %.1f %% of the samples, worst difference %.5f\n",
              100.0 * double(thinned_samples) / double(exact_samples), worst);
}

TEST(VolumeMarch, MaximumIntensityProjectionIsTheLargestSample) {
  const auto g = make_sphere_distance(21);
  const Macrocells m = build_macrocells(*g);
  auto tf = TransferFunction::preset("grayscale", g->min_value, g->max_value, "tf");
  MarchSetup s{g.get(), &m, nullptr, &*tf, 0.5f};
  // Through the centre along x: the largest distance is at the ends, 10 voxels from the centre
  // less the first sample's half step.
  float v = 0.0f;
  ASSERT_TRUE(march_maximum(s, Vec3(-5.0f, 10.0f, 10.0f), Vec3(1, 0, 0), 0.0f, 100.0f, v));
  EXPECT_NEAR(v, 9.75f, 1e-4f);
  // Against every sample, brute force.
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 20.0f);
  for (int i = 0; i < 100; ++i) {
    const Vec3 from(u(rng), u(rng), -4.0f), to(u(rng), u(rng), 24.0f);
    const Vec3 d = to - from;
    float best = -1.0f, got = 0.0f;
    float a = 0.0f, b = 1e30f;
    if (!clip_to_box(Vec3(0.0f), Vec3(20.0f), from, d, a, b)) continue;
    const float dt = 0.5f / glm::length(d);
    // Stretches [k dt, (k + 1) dt] overlapping [a, b], each sampled at its middle (kept in the grid).
    for (int64_t k = int64_t(std::floor(a / dt)); float(k) * dt < b; ++k)
      best = std::max(best, trilinear_value(*g, glm::clamp(from + (float(k) + 0.5f) * dt * d, Vec3(0.0f), Vec3(20.0f))));
    ASSERT_TRUE(march_maximum(s, from, d, 0.0f, 1e30f, got));
    EXPECT_NEAR(got, best, 1e-4f) << i;
  }
  EXPECT_FALSE(march_maximum(s, Vec3(-5.0f, 30.0f, 10.0f), Vec3(1, 0, 0), 0.0f, 100.0f, v));  // misses
}

TEST(TransferFunction, PointsAreCheckedAndPresetsExist) {
  const auto bad = [](std::vector<TransferPoint> p, const char* says) {
    auto r = TransferFunction::make(std::move(p), "objects[0].transfer");
    ASSERT_FALSE(r) << says;
    EXPECT_NE(r.error().message.find(says), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.rfind("objects[0].transfer", 0), 0u);
  };
  bad({{0.0f, Vec3(1.0f), 0.5f}}, "at least two points");
  bad({{1.0f, Vec3(1.0f), 0.5f}, {0.5f, Vec3(1.0f), 0.5f}}, "increase strictly");
  bad({{0.0f, Vec3(1.0f), 0.5f}, {1.0f, Vec3(1.0f), 1.5f}}, "opacity must be in [0, 1]");
  bad({{0.0f, Vec3(-1.0f), 0.5f}, {1.0f, Vec3(1.0f), 0.5f}}, "non-negative");
  bad({{0.0f, Vec3(1.0f), 0.5f}, {NAN, Vec3(1.0f), 0.5f}}, "finite");
  for (const char* name : {"ct-bone", "ct-skin", "grayscale", "hot", "cool-warm"})
    EXPECT_TRUE(TransferFunction::preset(name, 0.0f, 100.0f, "tf")) << name;
  auto unknown = TransferFunction::preset("rainbow", 0.0f, 1.0f, "tf");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find("ct-bone"), std::string::npos);
  auto tf = *TransferFunction::make({{0.0f, Vec3(0.0f), 0.0f}, {10.0f, Vec3(1.0f), 1.0f}}, "tf");
  Vec3 c;
  float a;
  tf.lookup(5.0f, c, a);
  EXPECT_NEAR(a, 0.5f, 1e-3f);
  EXPECT_NEAR(tf.max_opacity(0.0f, 2.0f), 0.2f, 0.02f);
}

}  // namespace
}  // namespace frameless
