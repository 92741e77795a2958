// Image-based environments (settings.environment, core/scene/environment.h): the map's density
// integrates to one and matches its samples, a white furnace inside a uniform map stays white,
// light sampling, BSDF sampling and MIS agree under a non-uniform map, Whitted sees the map, and
// bad files or fields give one-line errors. Statistical checks: fixed seeds, 5 standard errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "core/base/rng.h"
#include "core/io/scene_json.h"
#include "core/shading/path_tracer.h"
#include "path_estimate.h"
#include "core/shading/shading.h"
#include "exr_writer.h"

namespace frameless {
namespace {

using testing::estimate;
using testing::Estimate;
using testing::make_ray;

namespace fs = std::filesystem;

fs::path dir() {
  static const fs::path d = [] {
    const fs::path p = fs::temp_directory_path() / ("frameless_env_" + std::to_string(::getpid()));
    fs::create_directories(p);
    return p;
  }();
  return d;
}

// A w x h RGB map: value(x, y) per channel.
template <class F>
std::string write_map(const std::string& name, int w, int h, F value) {
  std::vector<std::vector<float>> planes(3, std::vector<float>(size_t(w) * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) planes[size_t(c)][size_t(y) * w + x] = value(x, y, c);
  const std::string path = (dir() / name).string();
  testing::write_exr(path, w, h, {"B", "G", "R"}, {planes[2], planes[1], planes[0]});
  return path;
}

Result<std::unique_ptr<Scene>> scene_with(const std::string& env, const std::string& rest) {
  return parse_scene_json(R"({"settings":{"integrator":"path","max_depth":1000,"environment":)" + env +
                              R"(},"ambient":{"type":"none"},)" + rest + "}",
                          (dir() / "s.json").string(), dir().string());
}

// A scene needs an object: a speck far below everything the tests look at.
const std::string kSpeck =
    R"("materials":{"d":{"class":"diffuse"}},"objects":[{"type":"sphere","center":[0,-1000,0],"radius":0.01,"material":"d"}])";

// A bright patch above and to one side, a dim sky elsewhere.
float patchy(int x, int y, int) { return (x >= 5 && x < 8 && y >= 2 && y < 4) ? 40.0f : 0.2f; }

TEST(Environment, DensityIntegratesToOneAndMatchesItsSamples) {
  const std::string file = write_map("patchy.exr", 16, 8, patchy);
  auto s = scene_with(R"({"file":")" + file + R"(","rotate":30})", kSpeck);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const EnvironmentMap& env = *(*s)->environment;
  // E[pdf(d)] over uniform directions d is the integral of pdf / (4 pi).
  Rng rng(3);
  double sum = 0;
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const float z = 1.0f - 2.0f * rng.next_float(), phi = 2.0f * kPi * rng.next_float();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    sum += env.pdf(Vec3(r * std::cos(phi), z, r * std::sin(phi))) * 4.0 * kPi;
  }
  EXPECT_NEAR(sum / n, 1.0, 0.02);
  // Samples report the density of where they land, and land mostly on the bright patch.
  int bright = 0;
  for (int i = 0; i < 10000; ++i) {
    Vec3 d;
    float pdf;
    ASSERT_TRUE(env.sample(rng.next_float(), rng.next_float(), d, pdf));
    EXPECT_NEAR(pdf, env.pdf(d), 1e-3f * pdf);
    bright += env.radiance(d).x > 1.0f;
  }
  EXPECT_GT(bright, 9000);
}

TEST(Environment, WhiteFurnaceInsideAUniformMap) {
  const std::string file = write_map("white.exr", 16, 8, [](int, int, int) { return 1.0f; });
  auto s = scene_with(R"({"file":")" + file + R"("})",
                      R"("materials":{"w":{"class":"diffuse","kd":1}},
                         "objects":[{"type":"sphere","center":[0,0,0],"radius":1,"material":"w"}])");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Estimate e = estimate(**s, make_ray(Vec3(0, 0, 4), Vec3(0.3f, 0.2f, -1)), 20000, 5);
  EXPECT_NEAR(e.mean, 1.0, 5 * e.se + 1e-4);
}

TEST(Environment, LightSamplingBsdfSamplingAndMisAgree) {
  const std::string file = write_map("patchy2.exr", 16, 8, patchy);
  auto s = scene_with(R"({"file":")" + file + R"(","scale":0.5})",
                      R"("materials":{"f":{"class":"diffuse","kd":0.5}},
                         "objects":[{"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":40,"material":"f"}])");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Ray ray = make_ray(Vec3(0, 3, 3), Vec3(0.1f, -3, -3));
  PathOptions mis, light, bsdf;
  mis.max_bounces = light.max_bounces = bsdf.max_bounces = 1;
  light.strategy = LightStrategy::kLightOnly;
  bsdf.strategy = LightStrategy::kBsdfOnly;
  const Estimate a = estimate(**s, ray, 50000, 1, mis), b = estimate(**s, ray, 50000, 2, light),
                 c = estimate(**s, ray, 200000, 3, bsdf);
  EXPECT_NEAR(a.mean, b.mean, 5 * std::hypot(a.se, b.se));
  EXPECT_NEAR(a.mean, c.mean, 5 * std::hypot(a.se, c.se));
  // Importance sampling pays: light sampling beats BSDF sampling per path on a patchy sky.
  EXPECT_LT(b.se, c.se);
}

TEST(Environment, WhittedSeesTheMapWhereRaysEscape) {
  const std::string file = write_map("rows.exr", 4, 2, [](int, int y, int c) { return y == 0 ? 2.0f + c : 0.5f; });
  auto s = scene_with(R"({"file":")" + file + R"(","scale":2})", kSpeck);
  ASSERT_TRUE(s.ok()) << s.error().message;
  (*s)->settings.integrator = Integrator::kWhitted;
  const Vec3 up = trace_radiance(**s, make_ray(Vec3(0), Vec3(0.1f, 1, 0)), 0, Vec3(1.0f), nullptr);
  const Vec3 down = trace_radiance(**s, make_ray(Vec3(0), Vec3(0.1f, -1, 0)), 0, Vec3(1.0f), nullptr);
  EXPECT_EQ(up, Vec3(4.0f, 6.0f, 8.0f));
  EXPECT_EQ(down, Vec3(1.0f));
}

TEST(Environment, RadianceHdrMapsLoadLikeExr) {
  // A 4 x 2 .hdr (flat scanlines): the top row (64, 96, 128 | e 131), the bottom (128 x 3 | e 128).
  std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n";
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) hdr += y == 0 ? std::string{64, 96, char(128), char(131)} : std::string(4, char(128));
  const std::string file = (dir() / "rows.hdr").string();
  { std::ofstream(file, std::ios::binary) << hdr; }
  auto s = scene_with(R"({"file":")" + file + R"(","scale":2})", kSpeck);
  ASSERT_TRUE(s.ok()) << s.error().message;
  (*s)->settings.integrator = Integrator::kWhitted;
  const Vec3 up = trace_radiance(**s, make_ray(Vec3(0), Vec3(0.1f, 1, 0)), 0, Vec3(1.0f), nullptr);
  const Vec3 down = trace_radiance(**s, make_ray(Vec3(0), Vec3(0.1f, -1, 0)), 0, Vec3(1.0f), nullptr);
  EXPECT_EQ(up, 2.0f * Vec3(64.5f, 96.5f, 128.5f) / 32.0f);  // (m + 0.5) 2^(e - 136), times scale
  EXPECT_EQ(down, 2.0f * Vec3(128.5f / 256.0f));
}

TEST(Environment, BadFilesAndFieldsGiveOneLineErrors) {
  const std::string neg = write_map("neg.exr", 4, 2, [](int x, int, int) { return x == 1 ? -1.0f : 1.0f; });
  const std::string nan = write_map("nan.exr", 4, 2, [](int x, int, int) {
    return x == 2 ? std::numeric_limits<float>::quiet_NaN() : 1.0f;
  });
  const std::string big = write_map("wide.exr", 16385, 1, [](int, int, int) { return 1.0f; });
  const std::string ok = write_map("ok.exr", 4, 2, [](int, int, int) { return 1.0f; });
  { std::ofstream((dir() / "corrupt.exr").string()) << "v/1\x01 not an exr"; }
  const struct {
    std::string env, expect;
  } cases[] = {
      {R"({"file":"missing.exr"})", "missing.exr"},
      {R"({"file":"corrupt.exr"})", "corrupt.exr"},
      {R"({"file":")" + neg + R"("})", "negative"},
      {R"({"file":")" + big + R"("})", "too large"},
      {R"({"file":")" + ok + R"(","scale":-1})", "settings.environment.scale"},
      {R"({"file":")" + ok + R"(","rotate":"x"})", "settings.environment.rotate"},
      {R"({"file":")" + ok + R"(","gamma":2})", "settings.environment.gamma"},
      {R"({"rotate":3})", "settings.environment.file"},
  };
  // Non-finite texels read as 0, as for every image (core/io/image_io.h): not an error.
  auto with_nan = scene_with(R"({"file":")" + nan + R"("})", kSpeck);
  ASSERT_TRUE(with_nan.ok()) << with_nan.error().message;
  EXPECT_EQ((*with_nan)->environment->radiance(Vec3(0, 0, 1)), Vec3(0.0f));  // u = 0.5: column 2
  EXPECT_EQ((*with_nan)->environment->radiance(Vec3(0, 0, -1)), Vec3(1.0f));
  for (const auto& c : cases) {
    auto s = scene_with(c.env, kSpeck);
    ASSERT_FALSE(s.ok()) << c.env;
    const std::string& m = s.error().message;
    EXPECT_NE(m.find(c.expect), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace frameless
