// Parker's four classes through the shader interface (core/shading/parker_shaders.h): scenes may
// name them as shaders, checked by their declarations, and get the compiled class; their shade()
// functions, written against the interface alone, give the compiled kernel's image.
#include <gtest/gtest.h>

#include <cmath>

#include "core/io/scene_json.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "core/shading/parker_shaders.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

Result<std::unique_ptr<Scene>> parse_material(const std::string& material) {
  return parse_scene_json(R"({"materials":{"m":)" + material +
                              R"(},"objects":[{"type":"sphere","center":[0,0,0],"radius":1,"material":"m"}]})",
                          "s.json", "/nonexistent");
}

TEST(ParkerShaders, NamedAsShadersTheyAreTheCompiledClasses) {
  const std::pair<const char*, const char*> same[] = {
      {R"({"shader":"polished","params":{"kd":[0.5,0.4,0.3],"r0":0.05,"kh":[0.2,0.2,0.2],"phong_exponent":50}})",
       R"({"class":"polished","kd":[0.5,0.4,0.3],"r0":0.05,"kh":0.2,"phong_exponent":50})"},
      {R"({"shader":"metal","params":{"ks":[0.9,0.8,0.5],"phong_exponent":300}})",
       R"({"class":"metal","ks":[0.9,0.8,0.5],"phong_exponent":300})"},
      {R"({"shader":"dielectric","params":{"ior":1.33,"extinction":[0.1,0.2,0.3]}})",
       R"({"class":"dielectric","ior":1.33,"extinction":[0.1,0.2,0.3]})"},
      {R"({"shader":"diffuse","params":{"kd":[0.1,0.2,0.3]}})", R"({"class":"diffuse","kd":[0.1,0.2,0.3]})"},
  };
  for (const auto& [shader, cls] : same) {
    auto a = parse_material(shader), b = parse_material(cls);
    ASSERT_TRUE(a) << a.error().message;
    ASSERT_TRUE(b) << b.error().message;
    const MaterialParams &x = (*a)->materials[0], &y = (*b)->materials[0];
    EXPECT_EQ(x.cls, y.cls) << shader;
    EXPECT_EQ(x.kd, y.kd);
    EXPECT_EQ(x.ks, y.ks);
    EXPECT_EQ(x.kh, y.kh);
    EXPECT_EQ(x.r0, y.r0);
    EXPECT_EQ(x.ior, y.ior);
    EXPECT_EQ(x.extinction, y.extinction);
    EXPECT_EQ(x.phong_exponent, y.phong_exponent);
    EXPECT_TRUE((*a)->shaders.empty()) << "built in, run as compiled";
  }
  // Checked by their declarations like any plug-in.
  auto typo = parse_material(R"({"shader":"polished","params":{"kS":0.5}})");
  ASSERT_FALSE(typo);
  EXPECT_NE(typo.error().message.find("it declares kd, r0, kh, phong_exponent"), std::string::npos) << typo.error().message;
  auto range = parse_material(R"({"shader":"polished","params":{"r0":[0.5,2,0.5]}})");
  ASSERT_FALSE(range);
  EXPECT_NE(range.error().message.find("materials.m.params.r0[1]"), std::string::npos) << range.error().message;
}

TEST(ParkerShaders, TheirInterfaceShadeGivesTheCompiledImage) {
  // The default scene holds all four classes; its dielectric's absorption is not expressible
  // through the interface (no media), so that material alone stays compiled.
  auto compiled = load_scene("default");
  auto routed = load_scene("default");
  ASSERT_TRUE(compiled && routed);
  const int n = route_through_interface(**routed);
  EXPECT_GE(n, 3);
  finalize_scene(**routed);
  const CameraBasis cam = make_camera_basis((*compiled)->camera, 64, 48);
  float worst = 0.0f;
  int lit = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const Ray r = camera_ray(cam, x + 0.5f, y + 0.5f);
      const Vec3 a = testing::radiance_along(**compiled, r.org, r.dir), b = testing::radiance_along(**routed, r.org, r.dir);
      worst = std::max(worst, max_component(glm::abs(a - b)));
      lit += max_component(a) > 0.05f;
    }
  EXPECT_LT(worst, 2e-4f);
  EXPECT_GT(lit, 1000);
}

}  // namespace
}  // namespace frameless
