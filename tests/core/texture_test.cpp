// Texture sampling: bilinear filtering, wrap and clamp, sRGB, UV transform; Perlin noise and the
// procedural solids.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/scene/texture.h"

namespace frameless {
namespace {

// ---- sampling ----

std::shared_ptr<const Image> grey_image(int w, int h, std::vector<uint8_t> texels) {
  auto img = std::make_shared<Image>();
  img->width = w;
  img->height = h;
  img->channels = 1;
  img->ldr = std::move(texels);
  return img;
}

float grey_at(const Texture& tex, float u, float v = 0.5f) {
  return sample_texture(tex, {Vec2(u, v), Vec3(0)}).x;
}

TEST(TextureSample, BilinearBetweenTexelCentres) {
  Texture tex;
  tex.image = grey_image(2, 1, {0, 200});
  tex.srgb = false;
  EXPECT_FLOAT_EQ(grey_at(tex, 0.25f), 0.0f);
  EXPECT_FLOAT_EQ(grey_at(tex, 0.75f), 200.0f / 255.0f);
  EXPECT_FLOAT_EQ(grey_at(tex, 0.5f), 100.0f / 255.0f);
  EXPECT_FLOAT_EQ(grey_at(tex, 0.375f), 50.0f / 255.0f);
  const Vec4 c = sample_texture(tex, {Vec2(0.5f), Vec3(0)});
  EXPECT_EQ(c.y, c.x);
  EXPECT_EQ(c.z, c.x);
  EXPECT_EQ(c.w, 1.0f);
}

TEST(TextureSample, RowZeroIsTheTop) {
  auto img = std::make_shared<Image>();
  img->width = 1;
  img->height = 2;
  img->channels = 3;
  img->ldr = {255, 0, 0, 0, 0, 255};  // row 0 red, row 1 blue
  Texture tex;
  tex.image = img;
  tex.wrap = TextureWrap::kClamp;
  EXPECT_EQ(sample_texture(tex, {Vec2(0.5f, 0.75f), Vec3(0)}), Vec4(1, 0, 0, 1));
  EXPECT_EQ(sample_texture(tex, {Vec2(0.5f, 0.25f), Vec3(0)}), Vec4(0, 0, 1, 1));
  EXPECT_EQ(sample_texture(tex, {Vec2(0.5f, 0.5f), Vec3(0)}), Vec4(0.5f, 0, 0.5f, 1));
}

TEST(TextureSample, RepeatWrapsFractionally) {
  Texture tex;
  tex.image = grey_image(4, 1, {0, 80, 160, 240});
  tex.srgb = false;
  EXPECT_FLOAT_EQ(grey_at(tex, 1.25f), grey_at(tex, 0.25f));
  EXPECT_FLOAT_EQ(grey_at(tex, 0.25f), 40.0f / 255.0f);
  EXPECT_NEAR(grey_at(tex, -0.7f), grey_at(tex, 0.3f), 1e-5f);
  EXPECT_NEAR(grey_at(tex, -3.7f), grey_at(tex, 0.3f), 1e-5f);
  // Across the seam: u = 0.05 blends the last texel (0.3) with the first (0.7).
  EXPECT_NEAR(grey_at(tex, 0.05f), 0.3f * 240.0f / 255.0f, 1e-5f);
  EXPECT_NEAR(grey_at(tex, 0.5f, 7.3f), grey_at(tex, 0.5f, -0.7f), 1e-5f);
}

TEST(TextureSample, ClampHoldsEdgeTexels) {
  Texture tex;
  tex.image = grey_image(4, 1, {0, 80, 160, 240});
  tex.srgb = false;
  tex.wrap = TextureWrap::kClamp;
  EXPECT_EQ(grey_at(tex, -3.0f), 0.0f);
  EXPECT_EQ(grey_at(tex, 0.05f), 0.0f);
  EXPECT_FLOAT_EQ(grey_at(tex, 5.0f), 240.0f / 255.0f);
  EXPECT_FLOAT_EQ(grey_at(tex, 0.99f), 240.0f / 255.0f);
  EXPECT_FLOAT_EQ(grey_at(tex, 0.5f), 120.0f / 255.0f);
}

TEST(TextureSample, UvTransformScalesThenOffsets) {
  Texture tex;
  tex.image = grey_image(4, 1, {0, 80, 160, 240});
  tex.srgb = false;
  EXPECT_FLOAT_EQ(grey_at(tex, 0.5f), 120.0f / 255.0f);
  tex.uv_scale = Vec2(2.0f, 1.0f);
  tex.uv_offset = Vec2(0.25f, 0.0f);
  EXPECT_FLOAT_EQ(grey_at(tex, 0.5f), 40.0f / 255.0f);  // u' = 1.25, wraps to 0.25
  EXPECT_FLOAT_EQ(grey_at(tex, 0.0f), 40.0f / 255.0f);  // u' = 0.25
}

TEST(TextureSample, GreyAlphaAndFloatChannels) {
  auto ga = std::make_shared<Image>();
  ga->width = ga->height = 1;
  ga->channels = 2;
  ga->ldr = {255, 51};
  Texture tex;
  tex.image = ga;
  const Vec4 c = sample_texture(tex, {Vec2(0.3f), Vec3(0)});
  EXPECT_EQ(Vec3(c), Vec3(1.0f));
  EXPECT_NEAR(c.w, 0.2f, 1e-6f);
  auto hdr = std::make_shared<Image>();
  hdr->width = hdr->height = 1;
  hdr->channels = 3;
  hdr->hdr = {2.5f, -1.0f, 100.0f};
  tex.image = hdr;  // float texels are never sRGB-decoded
  EXPECT_EQ(sample_texture(tex, {Vec2(0.3f), Vec3(0)}), Vec4(2.5f, -1.0f, 100.0f, 1.0f));
}

TEST(TextureSample, NeverNonFinite) {
  Texture tex;
  tex.image = grey_image(4, 3, std::vector<uint8_t>(12, 99));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (TextureWrap wrap : {TextureWrap::kRepeat, TextureWrap::kClamp}) {
    tex.wrap = wrap;
    for (float u : {nan, kInfinity, -kInfinity, 1e30f, -1e30f, -1e-30f, 0.0f, 1.0f}) {
      const Vec4 c = sample_texture(tex, {Vec2(u, -u), Vec3(0)});
      EXPECT_TRUE(is_finite(Vec3(c)) && std::isfinite(c.w)) << u;
      EXPECT_FLOAT_EQ(c.x, sample_texture(tex, {Vec2(0.5f), Vec3(0)}).x) << u;
    }
  }
}

// ---- noise and solids ----

TEST(TextureNoise, ZeroAtLatticePoints) {
  for (int x = -4; x <= 4; ++x)
    for (int y = -4; y <= 4; ++y)
      for (int z = -4; z <= 4; ++z) EXPECT_EQ(perlin_noise(Vec3(x, y, z) * 3.0f), 0.0f);
  EXPECT_NE(perlin_noise(Vec3(0.3f, 0.6f, 0.2f)), 0.0f);
}

TEST(TextureNoise, StaysInRangeAndSpreads) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> d(-100.0f, 100.0f);
  float lo = 1.0f, hi = -1.0f;
  double sum = 0.0;
  for (int i = 0; i < 100000; ++i) {
    const float n = perlin_noise(Vec3(d(rng), d(rng), d(rng)));
    ASSERT_TRUE(n >= -1.0f && n <= 1.0f) << n;
    lo = std::min(lo, n);
    hi = std::max(hi, n);
    sum += n;
  }
  EXPECT_LT(lo, -0.6f);
  EXPECT_GT(hi, 0.6f);
  EXPECT_LT(std::abs(sum / 100000.0), 0.02);
}

TEST(TextureNoise, ContinuousPeriodicAndSafe) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> d(-20.0f, 20.0f);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(d(rng), d(rng), d(rng));
    const float n = perlin_noise(p);
    for (int axis = 0; axis < 3; ++axis) {
      Vec3 q = p;
      q[axis] += 1e-4f;
      EXPECT_LT(std::abs(perlin_noise(q) - n), 2e-3f) << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_NEAR(perlin_noise(p + Vec3(256.0f, -512.0f, 0.0f)), n, 1e-3f);
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(perlin_noise(Vec3(nan, 0.5f, 0.5f)), 0.0f);
  EXPECT_EQ(perlin_noise(Vec3(kInfinity, 0.5f, 0.5f)), 0.0f);
  EXPECT_TRUE(std::isfinite(perlin_noise(Vec3(3e38f, 0.5f, -0.25f))));
}

TEST(TextureNoise, TurbulenceSumsOctaves) {
  const Vec3 p(1.3f, -2.7f, 0.45f);
  EXPECT_EQ(turbulence(p, 1), std::abs(perlin_noise(p)));
  EXPECT_FLOAT_EQ(turbulence(p, 3), std::abs(perlin_noise(p)) +
                                        std::abs(perlin_noise(p * 2.0f)) / 2.0f +
                                        std::abs(perlin_noise(p * 4.0f)) / 4.0f);
  EXPECT_EQ(turbulence(p, 0), 0.0f);
}

Vec3 checker_at(const Texture& tex, Vec3 p) { return Vec3(sample_texture(tex, {Vec2(0), p})); }

TEST(TextureSolid, CheckerParityHoldsAcrossZero) {
  Texture tex;
  tex.kind = TextureKind::kChecker;
  tex.color_a = Vec3(1, 0, 0);
  tex.color_b = Vec3(0, 0, 1);
  EXPECT_EQ(checker_at(tex, Vec3(0.5f, 0.5f, 0.5f)), tex.color_a);
  EXPECT_EQ(checker_at(tex, Vec3(-0.5f, 0.5f, 0.5f)), tex.color_b);
  EXPECT_EQ(checker_at(tex, Vec3(-1.5f, 0.5f, 0.5f)), tex.color_a);
  EXPECT_EQ(checker_at(tex, Vec3(-0.5f, -0.5f, 0.5f)), tex.color_a);
  EXPECT_EQ(checker_at(tex, Vec3(-0.5f, -0.5f, -0.5f)), tex.color_b);
  EXPECT_EQ(checker_at(tex, Vec3(-2.5f, 0.5f, 0.5f)), tex.color_b);
  tex.frequency = 2.0f;  // cells of 0.5
  EXPECT_EQ(checker_at(tex, Vec3(0.25f, 0.25f, 0.25f)), tex.color_a);
  EXPECT_EQ(checker_at(tex, Vec3(0.75f, 0.25f, 0.25f)), tex.color_b);
  EXPECT_EQ(checker_at(tex, Vec3(-0.25f, 0.25f, 0.25f)), tex.color_b);
  tex.frequency = 1.0f;
  tex.to_texture = glm::mat4(1.0f);
  tex.to_texture[3] = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);  // shift x by one cell
  EXPECT_EQ(checker_at(tex, Vec3(0.5f, 0.5f, 0.5f)), tex.color_b);
}

TEST(TextureSolid, ProceduralColoursStayBetweenTheTwo) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> d(-20.0f, 20.0f);
  for (TextureKind kind :
       {TextureKind::kNoise, TextureKind::kTurbulence, TextureKind::kMarble, TextureKind::kWood}) {
    Texture tex;
    tex.kind = kind;
    tex.color_a = Vec3(0.9f, 0.2f, 0.5f);
    tex.color_b = Vec3(0.1f, 0.8f, 0.3f);
    tex.frequency = 0.7f;
    const Vec3 lo = glm::min(tex.color_a, tex.color_b), hi = glm::max(tex.color_a, tex.color_b);
    float t_min = 1.0f, t_max = 0.0f;
    for (int i = 0; i < 10000; ++i) {
      const Vec4 c = sample_texture(tex, {Vec2(0), Vec3(d(rng), d(rng), d(rng))});
      ASSERT_TRUE(is_finite(Vec3(c))) << int(kind);
      for (int k = 0; k < 3; ++k) {
        ASSERT_GE(c[k], lo[k] - 1e-6f) << int(kind);
        ASSERT_LE(c[k], hi[k] + 1e-6f) << int(kind);
      }
      EXPECT_EQ(c.w, 1.0f);
      const float t = (c.x - tex.color_b.x) / (tex.color_a.x - tex.color_b.x);
      t_min = std::min(t_min, t);
      t_max = std::max(t_max, t);
    }
    EXPECT_GT(t_max - t_min, 0.5f) << int(kind);  // the pattern varies
  }
}

}  // namespace
}  // namespace frameless
