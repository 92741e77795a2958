// Emitting materials: JSON "emission" and MTL Ke read and checked (one-line errors for negative,
// non-numeric or absurd values), and every integrator, today Whitted's, shows an emitter's
// radiance where a ray hits it, directly and in a mirror.
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/io/image_io.h"
#include "core/io/mesh_readers.h"
#include "core/io/scene_json.h"
#include "core/scene/scene_finalize.h"
#include "core/shading/shading.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

Result<std::unique_ptr<Scene>> parse(const std::string& materials, const std::string& extra = "") {
  // A unit quad at z = 0 facing +z, seen from z = 3; no lights, no ambient, black background.
  return parse_scene_json(R"({"ambient":{"type":"none"},"materials":{)" + materials + R"(},
      "objects":[{"type":"plane","point":[0,0,0],"normal":[0,0,1],"size":1,"material":"e"})" +
                              extra + R"(],
      "camera":{"eye":[0,0,3],"look":[0,0,0],"up":[0,1,0],"fov":30}})",
                          "t.json", ".");
}

using testing::radiance_along;

TEST(Emission, JsonEmitterIsSeenWithItsRadiance) {
  auto s = parse(R"("e":{"class":"diffuse","kd":0,"emission":[2,3,0.5]})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_TRUE((*s)->features.has_emission);
  EXPECT_EQ(radiance_along(**s, Vec3(0, 0, 3), Vec3(0, 0, -1)), Vec3(2.0f, 3.0f, 0.5f));
  EXPECT_EQ(radiance_along(**s, Vec3(2, 0, 3), Vec3(0, 0, -1)), Vec3(0.0f));  // misses the quad
  // An emitter also reflects: its diffuse part lit by the ambient adds to what it emits.
  auto lit = parse_scene_json(R"({"ambient":{"type":"constant","color":0.5},
      "materials":{"e":{"class":"diffuse","kd":0.5,"emission":1}},
      "objects":[{"type":"plane","point":[0,0,0],"normal":[0,0,1],"size":1,"material":"e"}]})",
                              "t.json", ".");
  ASSERT_TRUE(lit.ok()) << lit.error().message;
  EXPECT_EQ(radiance_along(**lit, Vec3(0, 0, 3), Vec3(0, 0, -1)), Vec3(1.25f));
}

TEST(Emission, MirrorShowsTheEmitter) {
  // A metal mirror at z = -1 facing +z behind the camera's view of the emitter: a ray from the
  // mirror's side sees k_s times the emission.
  auto s = parse(R"("e":{"class":"diffuse","kd":0,"emission":4},
                    "m":{"class":"metal","ks":0.5,"phong_exponent":1})",
                 R"(,{"type":"plane","point":[0,0,3],"normal":[0,0,-1],"size":10,"material":"m"})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  // From between the two, looking at the mirror: the reflected ray comes straight back to the quad.
  const Vec3 c = radiance_along(**s, Vec3(0, 0, 1), Vec3(0, 0, 1));
  EXPECT_NEAR(c.x, 2.0f, 1e-5f);
}

TEST(Emission, AnEmissionTextureAloneGivesTheRadiance) {
  auto s = parse_scene_json(R"({
      "textures":{"c":{"type":"checker","color_a":[3,2,1],"color_b":[3,2,1]}},
      "materials":{"e":{"class":"diffuse","kd":0,"emission_texture":"c"}},
      "ambient":{"type":"none"},
      "objects":[{"type":"plane","point":[0,0,0],"normal":[0,0,1],"size":1,"material":"e"}]})",
                            "t.json", ".");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ((*s)->materials.at(0).emission, Vec3(1.0f));
  const Vec3 c = radiance_along(**s, Vec3(0.1f, 0.1f, 3), Vec3(0, 0, -1));
  EXPECT_NEAR(c.x, 3.0f, 1e-5f);
  EXPECT_NEAR(c.z, 1.0f, 1e-5f);
}

TEST(Emission, ScenesWithoutEmittersSkipIt) {
  auto s = parse(R"("e":{"class":"diffuse","kd":0.5})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_FALSE((*s)->features.has_emission);
  EXPECT_EQ(radiance_along(**s, Vec3(0, 0, 3), Vec3(0, 0, -1)), Vec3(0.0f));
}

TEST(Emission, BadJsonEmissionIsAOneLineErrorNamingTheField) {
  const char* bad[] = {R"("e":{"class":"diffuse","emission":[1,-1,1]})",
                       R"("e":{"class":"diffuse","emission":"bright"})",
                       R"("e":{"class":"polished","emission":[1,2]})",
                       R"("e":{"class":"metal","emission":1e7})"};
  for (const char* m : bad) {
    SCOPED_TRACE(m);
    auto s = parse(m);
    ASSERT_FALSE(s.ok());
    const std::string& msg = s.error().message;
    EXPECT_NE(msg.find("t.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find("materials.e.emission"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

struct TempFiles {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("frameless_emission_" + std::to_string(::getpid()));
  TempFiles() { std::filesystem::create_directories(dir); }
  ~TempFiles() { std::filesystem::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

TEST(Emission, MtlKeBecomesEmissionAndNegativeKeIsAnError) {
  TempFiles t;
  const std::string obj = "mtllib e.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n";
  t.write("e.mtl", "newmtl lamp\nKd 0 0 0\nKe 2 3 4\n");
  ImageCache images;
  auto m = load_obj_with_materials(t.write("e.obj", obj), images);
  ASSERT_TRUE(m.ok()) << m.error().message;
  ASSERT_EQ(m->materials.size(), 1u);
  EXPECT_EQ(m->materials[0].emission, Vec3(2.0f, 3.0f, 4.0f));

  t.write("e.mtl", "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 -2 1\n");
  auto bad = load_obj_with_materials(t.write("e.obj", obj), images);
  ASSERT_FALSE(bad.ok());
  const std::string& msg = bad.error().message;
  EXPECT_NE(msg.find("e.mtl:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("emission must be >= 0"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
}

}  // namespace
}  // namespace frameless
