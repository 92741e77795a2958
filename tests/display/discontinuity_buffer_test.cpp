// igi's discontinuity buffer (display/discontinuity_buffer.h): the interleaving pattern of the
// indirect light disappears on a surface, direct light and texture stay sharp, and nothing mixes
// across a crease, a depth step, the sky or an emitter.
#include <gtest/gtest.h>

#include <functional>

#include "display/discontinuity_buffer.h"

namespace frameless {
namespace {

constexpr int kN = 3;  // interleaving window

struct View {
  DisplayImage img;
  std::vector<PointGuide> guides;
  std::vector<Vec3> indirect;
};

// A w x h image of the plane z = 0 (pixel (x, y) at (x, y, 0), normal +z) with albedo a(x, y),
// direct light d(x, y) and indirect light i(x, y) (what igi's VPLs brought, before albedo).
View plane(int w, int h, std::function<Vec3(int, int)> a, std::function<Vec3(int, int)> d,
           std::function<Vec3(int, int)> i) {
  View v;
  v.img.reset(w, h);
  v.guides.resize(size_t(w) * h);
  v.indirect.resize(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t k = size_t(y) * w + x;
      v.guides[k] = {Vec3(float(x), float(y), 0.0f), kPointStatic, pack_normal(Vec3(0, 0, 1)), pack_albedo(a(x, y))};
      // The albedo as the filter will read it back (8 bits a channel).
      v.indirect[k] = unpack_albedo(v.guides[k].albedo) * i(x, y);
      const Vec3 c = d(x, y) + v.indirect[k];
      for (int ch = 0; ch < 3; ++ch) v.img.rgb[3 * k + ch] = c[ch];
    }
  return v;
}

Vec3 rgb(const View& v, int x, int y) {
  const size_t k = size_t(y) * v.img.width + x;
  return Vec3(v.img.rgb[3 * k], v.img.rgb[3 * k + 1], v.img.rgb[3 * k + 2]);
}

// Irradiance in a 3 x 3 pattern around 1 (each class a different VPL set), mean exactly 1.
Vec3 pattern(int x, int y) { return Vec3(1.0f + 0.4f * float((x % kN) - 1) + 0.2f * float((y % kN) - 1)); }

TEST(DiscontinuityBuffer, RemovesTheInterleavingPatternAndKeepsDirectLight) {
  const auto grey = [](int, int) { return Vec3(0.5f); };
  const auto direct = [](int x, int) { return Vec3(x < 6 ? 0.1f : 0.7f); };  // a sharp shadow edge
  View v = plane(12, 9, grey, direct, pattern);
  DiscontinuityBuffers scratch;
  filter_discontinuity(v.img, v.guides, v.indirect, kN, scratch);
  for (int y = 1; y < 8; ++y)
    for (int x = 1; x < 11; ++x) {
      // Every window holds each class once: the indirect light is the pattern's mean, 0.5 x 1.
      const float expect = direct(x, y).x + 0.5f * 1.0f;
      ASSERT_NEAR(rgb(v, x, y).x, expect, 2e-3f) << x << "," << y;  // the shadow edge stays sharp
    }
  // Without the filter the same pixels carry the pattern (the test would fail on them).
  const View raw = plane(12, 9, grey, direct, pattern);
  EXPECT_GT(std::abs(rgb(raw, 3, 3).x - (0.1f + 0.5f)), 0.05f);
}

TEST(DiscontinuityBuffer, TextureStaysSharpBecauseAlbedoIsDividedOut) {
  const auto checker = [](int x, int y) { return Vec3((x + y) % 2 ? 0.9f : 0.1f); };
  const auto none = [](int, int) { return Vec3(0.0f); };
  View v = plane(12, 9, checker, none, pattern);
  DiscontinuityBuffers scratch;
  filter_discontinuity(v.img, v.guides, v.indirect, kN, scratch);
  for (int y = 1; y < 8; ++y)
    for (int x = 1; x < 11; ++x)
      ASSERT_NEAR(rgb(v, x, y).x, unpack_albedo(v.guides[size_t(y) * 12 + x].albedo).x * 1.0f, 2e-3f) << x << "," << y;
}

TEST(DiscontinuityBuffer, NothingMixesAcrossCreasesStepsSkyOrEmitters) {
  const auto grey = [](int, int) { return Vec3(0.5f); };
  const auto none = [](int, int) { return Vec3(0.0f); };
  const auto two = [](int x, int) { return Vec3(x < 6 ? 0.2f : 1.8f); };  // uniform on each side
  for (int kind = 0; kind < 4; ++kind) {
    View v = plane(12, 9, grey, none, two);
    for (int y = 0; y < 9; ++y)
      for (int x = 6; x < 12; ++x) {
        PointGuide& g = v.guides[size_t(y) * 12 + x];
        if (kind == 0) g.normal = pack_normal(glm::normalize(Vec3(1, 0, 1)));  // a crease (45 degrees)
        if (kind == 1) g.p.z = -3.0f;                                          // a step in depth
        if (kind == 2) g.object = kPointSky;                                    // the sky
        if (kind == 3) g.albedo = 0;                                            // an emitter
      }
    const View before = v;
    DiscontinuityBuffers scratch;
    filter_discontinuity(v.img, v.guides, v.indirect, kN, scratch);
    for (int y = 1; y < 8; ++y)
      for (int x = 4; x < 8; ++x)
        ASSERT_NEAR(rgb(v, x, y).x, rgb(before, x, y).x, 1e-5f) << "kind " << kind << " at " << x << "," << y;
  }
}

TEST(DiscontinuityBuffer, SameSurfaceTest) {
  const PointGuide a{Vec3(0.0f), kPointStatic, pack_normal(Vec3(0, 0, 1)), pack_albedo(Vec3(0.5f))};
  PointGuide b = a;
  b.p = Vec3(1, 0, 0.05f);
  EXPECT_TRUE(same_surface(a, b));
  b.p = Vec3(1, 0, 0.2f);  // 11 degrees off the tangent plane
  EXPECT_FALSE(same_surface(a, b));
  b = a;
  b.normal = pack_normal(glm::normalize(Vec3(0.3f, 0, 1)));  // 17 degrees
  EXPECT_TRUE(same_surface(a, b));
  b.normal = pack_normal(glm::normalize(Vec3(0.6f, 0, 1)));  // 31 degrees
  EXPECT_FALSE(same_surface(a, b));
}

}  // namespace
}  // namespace frameless
