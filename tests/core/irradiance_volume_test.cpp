// The irradiance volume (Parker's radiosity-based ambient): harmonics that reproduce uniform and
// hemispherical skies (the cosine-convolved order-2 expansion is exact for both), vertices
// inside geometry left out, the Whitted integrator reading it as l_a(p, n), and bad fields.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/io/scene_json.h"
#include "core/scenes/scene_load.h"
#include "core/shading/irradiance_bake.h"
#include "core/shading/shading.h"
#include "exr_writer.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<Scene> baked(const std::string& json, const std::string& dir = ".") {
  auto s = parse_scene_json(json, "t.json", dir);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  if (!s.ok()) return nullptr;
  bake_irradiance_volume(**s);
  return std::move(*s);
}

// Two specks at opposite corners: the scene's bounds (the grid spans them), nothing that blocks
// the sky at the grid's vertices.
const char* kSpeck = R"("materials":{"d":{"class":"diffuse","kd":0.5}},
    "objects":[{"type":"sphere","center":[-10,-55,-10],"radius":0.01,"material":"d"},
               {"type":"sphere","center":[10,-45,10],"radius":0.01,"material":"d"}])";

TEST(IrradianceVolume, UniformSkyGivesPiFromEveryDirection) {
  auto s = baked(std::string(R"({"settings":{"background":1},
      "ambient":{"type":"irradiance_volume","resolution":2,"samples":1024},)") + kSpeck + "}");
  ASSERT_TRUE(s && s->ambient.volume);
  for (const Vec3& n : {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, -1, 0), glm::normalize(Vec3(1, 1, 1))}) {
    const Vec3 e = s->ambient.volume->irradiance(Vec3(0, -50, 0), n);
    EXPECT_NEAR(e.x, kPi, 0.02f * kPi) << n.x << " " << n.y;
  }
  // Whitted reads it as l_a = E / pi.
  EXPECT_NEAR(ambient_light(s->ambient, Vec3(0, -50, 0), Vec3(0, 1, 0)).y, 1.0f, 0.02f);
}

TEST(IrradianceVolume, HemisphericalSkyIsExact) {
  // Radiance 1 above the horizon, 0 below: E(n) = pi (1 + n.y) / 2.
  const fs::path dir = fs::temp_directory_path() / ("frameless_iv_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<float> plane(64 * 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) plane[size_t(y) * 64 + x] = y < 16 ? 1.0f : 0.0f;
  testing::write_exr((dir / "sky.exr").string(), 64, 32, {"B", "G", "R"}, {plane, plane, plane});
  auto s = baked(std::string(R"({"settings":{"environment":{"file":"sky.exr"}},
      "ambient":{"type":"irradiance_volume","resolution":1,"samples":4096},)") + kSpeck + "}",
                 dir.string());
  ASSERT_TRUE(s && s->ambient.volume);
  const IrradianceVolume& v = *s->ambient.volume;
  EXPECT_NEAR(v.irradiance(Vec3(0, -50, 0), Vec3(0, 1, 0)).x, kPi, 0.03f * kPi);
  EXPECT_NEAR(v.irradiance(Vec3(0, -50, 0), Vec3(1, 0, 0)).x, kPi / 2, 0.03f * kPi);
  EXPECT_NEAR(v.irradiance(Vec3(0, -50, 0), Vec3(0, -1, 0)).x, 0.0f, 0.03f * kPi);
}

TEST(IrradianceVolume, VerticesInsideGeometryAreLeftOut) {
  // A closed box on a wide floor: the grid's vertices inside the box see its back faces.
  auto s = baked(R"({"settings":{"background":1},
      "ambient":{"type":"irradiance_volume","resolution":8,"samples":64},
      "materials":{"d":{"class":"diffuse","kd":0.5}},
      "objects":[{"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":8,"material":"d"},
                 {"type":"box","min":[-1,0,-1],"max":[1,2,1],"material":"d"}]})");
  ASSERT_TRUE(s && s->ambient.volume);
  const IrradianceVolume& v = *s->ambient.volume;
  int inside = 0, inside_invalid = 0, outside = 0, outside_valid = 0;
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        const Vec3 p = v.vertex(i, j, k);
        const bool in = std::abs(p.x) < 0.9f && std::abs(p.z) < 0.9f && p.y > 0.1f && p.y < 1.9f;
        const bool out = std::abs(p.x) > 1.3f || std::abs(p.z) > 1.3f;
        inside += in, outside += out;
        inside_invalid += in && !v.valid[v.index(i, j, k)];
        outside_valid += out && v.valid[v.index(i, j, k)];
      }
  ASSERT_GT(inside, 0);
  EXPECT_EQ(inside_invalid, inside);
  EXPECT_EQ(outside_valid, outside);
  // Beside the box, facing it, the floor-level irradiance stays lit (no darkness leaks from inside).
  EXPECT_GT(v.irradiance(Vec3(1.05f, 0.5f, 0.0f), Vec3(1, 0, 0)).x, 1.0f);
}

TEST(IrradianceVolume, BadFieldsAreOneLineErrors) {
  for (const char* a : {R"({"type":"irradiance_volume","resolution":0})", R"({"type":"irradiance_volume","resolution":65})",
                        R"({"type":"irradiance_volume","samples":0})", R"({"type":"irradiance_volume","cells":4})"}) {
    auto s = parse_scene_json(std::string(R"({"ambient":)") + a + "," + kSpeck + "}", "t.json", ".");
    ASSERT_FALSE(s.ok()) << a;
    EXPECT_NE(s.error().message.find("ambient."), std::string::npos) << s.error().message;
    EXPECT_EQ(s.error().message.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace frameless
