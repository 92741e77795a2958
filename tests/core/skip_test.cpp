// Skip what a scene doesn't need: the analysis, the choice of shading path, and proof that each
// exact skip leaves the image bit-identical while the specialised path is really the one used.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "core/scene/scene_analysis.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "core/scenes/scene_variants.h"
#include "core/shading/render_sample.h"
#include "core/shading/shading.h"

namespace frameless {
namespace {

constexpr int kW = 64, kH = 48;

std::unique_ptr<Scene> load(const std::string& variant = "") {
  auto r = load_scene("default");
  EXPECT_TRUE(r.ok());
  std::unique_ptr<Scene> s = std::move(*r);
  if (!variant.empty()) {
    EXPECT_TRUE(apply_scene_variant(*s, variant));
  }
  return s;
}

// Two jittered samples per pixel of a small image through the public per-sample function.
std::vector<float> render(const Scene& scene) {
  const CameraBasis b = make_camera_basis(scene.camera, kW, kH);
  std::vector<float> out;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (uint32_t k = 0; k < 2; ++k) {
        const SampleResult r = render_sample(scene, b, x, y, k);
        EXPECT_TRUE(r.valid);
        out.insert(out.end(), {r.color.x, r.color.y, r.color.z});
      }
  return out;
}

bool bit_identical(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

double rmse(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += double(a[i] - b[i]) * double(a[i] - b[i]);
  return std::sqrt(s / double(a.size()));
}

SkipConfig all_off() {
  SkipConfig k;
  k.shadows = k.refraction = k.highlights = k.prune = k.any_hit = false;
  return k;
}

TEST(SceneAnalysis, FindsWhatTheDefaultSceneAndItsVariantsNeed) {
  auto s = load();
  EXPECT_TRUE(s->features.has_lights && s->features.has_dielectric && s->features.has_absorption);
  EXPECT_TRUE(s->features.has_highlights && s->features.has_ambient);
  EXPECT_FALSE(s->features.has_textures);  // no texture support: no path computes coordinates
  EXPECT_EQ(shade_path(*s), kShadeAll);
  EXPECT_EQ(shade_path(*load("no-lights")), kShadeRefraction | kShadeAbsorption);
  EXPECT_EQ(shade_path(*load("no-dielectric")), kShadeLights | kShadeHighlights);
  EXPECT_EQ(shade_path(*load("no-highlights")), kShadeAll & ~kShadeHighlights);
  // A switched-off skip keeps the general code.
  auto v = load("no-lights");
  v->settings.skips.shadows = false;
  EXPECT_EQ(shade_path(*v), kShadeAll);  // lights kept, so the highlights are too
  EXPECT_EQ(describe_shade_path(kShadeLights | kShadeHighlights), "lights+highlights");
  EXPECT_EQ(describe_shade_path(0), "minimal");
}

TEST(SceneAnalysis, BlackLightsAndClearGlassAreNotNeeds) {
  auto s = load();
  for (Light& l : s->lights) l.color = Vec3(0.0f);
  for (Material& m : s->materials) m.extinction = Vec3(0.0f);
  finalize_scene(*s);
  EXPECT_FALSE(s->features.has_lights);
  EXPECT_FALSE(s->features.has_absorption);
  EXPECT_EQ(shade_path(*s), kShadeRefraction);
}

// Each exact skip: the specialised path's image equals the general path's bit for bit.
TEST(SkipExactness, SpecialisedPathsAreBitIdenticalToTheGeneralPath) {
  for (const char* variant : {"", "no-lights", "no-dielectric", "no-highlights"}) {
    SCOPED_TRACE(variant);
    auto s = load(variant);
    s->settings.min_contribution = 1.0f / 512;
    const std::vector<float> fast = render(*s);
    SkipConfig general;  // pruning and any-hit stay on: only the specialisation is switched off
    general.shadows = general.refraction = general.highlights = false;
    s->settings.skips = general;
    ASSERT_EQ(shade_path(*s), kShadeAll);
    EXPECT_TRUE(bit_identical(fast, render(*s)));
  }
}

TEST(SkipExactness, AnyHitShadowRaysGiveTheSameImageAsClosestHit) {
  auto s = load();
  const std::vector<float> any = render(*s);
  s->settings.skips.any_hit = false;
  EXPECT_TRUE(bit_identical(any, render(*s)));
}

// Path tracing a scene without emitters under a black sky samples neither; sampling the black
// environment anyway (the skip off, as bench ablation times it: 14 % slower there) adds nothing.
TEST(SkipExactness, PathTracingWithoutEmittersSkipsTheirSamplingExactly) {
  auto s = load();
  s->settings.integrator = Integrator::kPath;
  s->settings.background = Vec3(0.0f);
  ASSERT_TRUE(s->emitters.empty());
  const std::vector<float> skipped = render(*s);
  s->settings.skips.emitters = false;
  EXPECT_TRUE(bit_identical(skipped, render(*s)));
  // A sky that is not black is sampled (and lights the image): the comparison has power.
  s->settings.skips.emitters = true;
  s->settings.background = Vec3(0.05f);
  EXPECT_FALSE(bit_identical(skipped, render(*s)));
}

// The dispatch bites: forcing a path without a bit the scene needs changes the image, so the
// bit-identity above compares two different compiled paths, not one path twice.
TEST(SkipExactness, ThePathChoiceReallyChangesTheCode) {
  auto s = load();
  const CameraBasis b = make_camera_basis(s->camera, kW, kH);
  int differ_lights = 0, differ_refraction = 0, differ_highlights = 0;
  for (int y = 0; y < kH; y += 2)
    for (int x = 0; x < kW; x += 2) {
      const Ray r = camera_ray(b, x + 0.5f, y + 0.5f);
      const Vec3 all = trace_radiance_path(*s, kShadeAll, r, 0, Vec3(1.0f), nullptr);
      differ_lights += all != trace_radiance_path(*s, kShadeAll & ~kShadeLights, r, 0, Vec3(1.0f), nullptr);
      differ_refraction += all != trace_radiance_path(*s, kShadeLights | kShadeHighlights, r, 0,
                                                      Vec3(1.0f), nullptr);
      differ_highlights += all != trace_radiance_path(*s, kShadeAll & ~kShadeHighlights, r, 0,
                                                      Vec3(1.0f), nullptr);
    }
  EXPECT_GT(differ_lights, 100);
  EXPECT_GT(differ_refraction, 10);  // the glass sphere's pixels
  EXPECT_GT(differ_highlights, 0);
}

// Pruning is not exact: bounded by the threshold. Each pruned branch has weight below
// min_contribution and carries radiance of at most about 1.5 in this scene (light + ambient), and a
// pixel prunes a handful of branches, so per-channel errors stay far below 0.02 and the RMSE below
// 2e-3; a threshold of 0.5 exceeds both (the test has power).
TEST(SkipPruning, PruningByContributionStaysWithinItsBound) {
  auto s = load();
  s->settings.skips = all_off();
  const std::vector<float> exact = render(*s);
  s->settings.skips = SkipConfig{};
  const std::vector<float> pruned = render(*s);
  EXPECT_FALSE(bit_identical(exact, pruned));
  float worst = 0;
  for (size_t i = 0; i < exact.size(); ++i) worst = std::max(worst, std::fabs(exact[i] - pruned[i]));
  EXPECT_LT(worst, 0.02f);
  EXPECT_LT(rmse(exact, pruned), 2e-3);
  s->settings.min_contribution = 0.5f;
  EXPECT_GT(rmse(exact, render(*s)), 2e-3);
}

}  // namespace
}  // namespace frameless
