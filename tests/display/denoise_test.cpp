// The display's a-trous denoiser (display/denoise.h): it keeps the mean of flat noisy regions,
// lowers their noise, stops at creases (normals) and steps (planes), divides out albedo so
// texture edges stay, and leaves the sky and emitters alone.
#include <gtest/gtest.h>

#include <cmath>

#include "core/base/rng.h"
#include "display/denoise.h"

namespace frameless {
namespace {

struct Scene2D {
  DisplayImage img;
  std::vector<PointGuide> guides;
};

// A w x h view of the plane z = 0 (normal +z), pixel (x, y) at (x, y, 0); colour c(x, y) plus
// uniform noise of half-width `noise` on luminance; albedo a(x, y).
template <class C, class A>
Scene2D plane(int w, int h, C colour, A albedo, float noise, uint64_t seed) {
  Scene2D s;
  s.img.reset(w, h);
  s.guides.resize(size_t(w) * h);
  Rng rng(seed);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const Vec3 c = colour(x, y) * (1.0f + noise * (2.0f * rng.next_float() - 1.0f));
      for (int k = 0; k < 3; ++k) s.img.rgb[3 * i + k] = c[k];
      s.img.sample_count[i] = 4;
      s.img.variance[i] = 4.0f * noise * noise / 3.0f * 0.1f;  // per-sample variance of the luminance
      s.guides[i].p = Vec3(float(x), float(y), 0.0f);
      s.guides[i].object = kPointStatic;
      s.guides[i].normal = pack_normal(Vec3(0, 0, 1));
      s.guides[i].albedo = pack_albedo(albedo(x, y));
    }
  return s;
}

double mean_x(const DisplayImage& img, int x0, int x1, int y0, int y1) {
  double s = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) s += img.rgb[3 * (size_t(y) * img.width + x)];
  return s / double((x1 - x0) * (y1 - y0));
}

double spread_x(const DisplayImage& img, int x0, int x1, int y0, int y1) {
  const double m = mean_x(img, x0, x1, y0, y1);
  double s = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const double d = img.rgb[3 * (size_t(y) * img.width + x)] - m;
      s += d * d;
    }
  return std::sqrt(s / double((x1 - x0) * (y1 - y0)));
}

TEST(Denoise, FlatNoisyPlaneKeepsItsMeanAndLosesItsNoise) {
  auto s = plane(64, 64, [](int, int) { return Vec3(0.3f); }, [](int, int) { return Vec3(0.5f); }, 0.5f, 1);
  const double m0 = mean_x(s.img, 8, 56, 8, 56), n0 = spread_x(s.img, 8, 56, 8, 56);
  DenoiseBuffers b;
  denoise_image(s.img, s.guides, 3, b);
  EXPECT_NEAR(mean_x(s.img, 8, 56, 8, 56), m0, 0.01 * m0);
  // The luminance weights are strict (1 standard deviation of the pixel's mean): a third at least.
  EXPECT_LT(spread_x(s.img, 8, 56, 8, 56), 0.67 * n0);
}

TEST(Denoise, AlbedoEdgesStaySharp) {
  // Uniform light 0.6 on a checkerboard of albedo 0.2 / 0.8: the shown colour is their product.
  auto a = [](int x, int y) { return ((x / 8 + y / 8) & 1) ? Vec3(0.8f) : Vec3(0.2f); };
  auto s = plane(64, 64, [&](int x, int y) { return 0.6f * a(x, y); }, a, 0.0f, 2);
  const std::vector<float> before = s.img.rgb;
  DenoiseBuffers b;
  denoise_image(s.img, s.guides, 3, b);
  for (size_t i = 0; i < before.size(); ++i) EXPECT_NEAR(s.img.rgb[i], before[i], 1e-2f * before[i] + 1e-5f) << i;
}

TEST(Denoise, CreasesAndStepsStopIt) {
  // Left half faces +z, right half faces +x: a crease; the filter must not mix 0.1 and 0.9.
  auto s = plane(64, 32, [](int x, int) { return Vec3(x < 32 ? 0.1f : 0.9f); }, [](int, int) { return Vec3(0.5f); },
                 0.2f, 3);
  for (int y = 0; y < 32; ++y)
    for (int x = 32; x < 64; ++x) s.guides[size_t(y) * 64 + x].normal = pack_normal(Vec3(1, 0, 0));
  DenoiseBuffers b;
  denoise_image(s.img, s.guides, 3, b);
  EXPECT_NEAR(mean_x(s.img, 28, 32, 0, 32), 0.1, 0.01);
  EXPECT_NEAR(mean_x(s.img, 32, 36, 0, 32), 0.9, 0.05);
}

TEST(Denoise, SkyAndEmittersAreLeftAlone) {
  auto s = plane(16, 16, [](int, int) { return Vec3(0.5f); }, [](int, int) { return Vec3(0.5f); }, 0.3f, 4);
  s.guides[5].object = kPointSky;
  s.guides[6].albedo = 0;  // an emitter
  s.img.rgb[15] = 7.0f;
  s.img.rgb[18] = 17.0f;
  DenoiseBuffers b;
  denoise_image(s.img, s.guides, 3, b);
  EXPECT_EQ(s.img.rgb[15], 7.0f);
  EXPECT_EQ(s.img.rgb[18], 17.0f);
  for (float v : s.img.rgb) EXPECT_LT(v, 2.0f + (v >= 7.0f ? 100.0f : 0.0f));  // no bleeding
}

}  // namespace
}  // namespace frameless
