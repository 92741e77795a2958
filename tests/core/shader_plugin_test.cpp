// Plug-in shaders (issue 28; include/frameless/shader.h): the example libraries load from the
// search path and shade as they say (Gooch warm towards the light and cool away from it, bricks
// and mortar, toon outlines), they are seen in mirrors and under path tracing (as their albedo),
// NaN from a plug-in never reaches a pixel, and every kind of bad library or parameter is one line.
#include <gtest/gtest.h>

#include <cmath>

#include "core/io/scene_json.h"
#include "core/io/shader_library.h"
#include "core/shading/render_sample.h"
#include "core/shading/shading.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

Result<std::unique_ptr<Scene>> parse(const std::string& materials, const std::string& objects,
                                     const std::string& extra = "") {
  set_shader_search_path({FRAMELESS_SHADER_DIR, FRAMELESS_TEST_SHADER_DIR});
  return parse_scene_json(R"({"camera":{"eye":[0,0,10],"look":[0,0,0]},"ambient":{"type":"constant","color":0.1},)" +
                              extra + R"("lights":[{"type":"point","position":[20,0,5],"color":1}],"materials":{)" +
                              materials + R"(},"objects":[)" + objects + "]}",
                          "/nonexistent/s.json", "/nonexistent");
}

using testing::radiance_along;

constexpr const char* kSphere = R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"m"})";

TEST(ShaderPlugin, GoochIsWarmTowardsTheLightAndCoolAway) {
  auto s = parse(R"("m":{"shader":"gooch","params":{"kd":[0.5,0.5,0.5],"shininess":0}})", kSphere);
  ASSERT_TRUE(s) << s.error().message;
  ASSERT_EQ((*s)->shaders.size(), 1u);
  EXPECT_EQ(std::string((*s)->shaders[0].shader->name), "gooch");
  // The light is at +x (and in front): the sphere's +x side faces it, its -x side faces away.
  const Vec3 lit = radiance_along(**s, Vec3(0.7f, 0, 10), Vec3(0, 0, -1));
  const Vec3 dark = radiance_along(**s, Vec3(-0.7f, 0, 10), Vec3(0, 0, -1));
  EXPECT_GT(lit.x, lit.z) << "warm: more red than blue";
  EXPECT_GT(dark.z, dark.x) << "cool: more blue than red";
  // The formula: t = (1 + n.l) / 2 with n = (0.7, 0, 0.714) and l towards (20, 0, 5).
  const Vec3 p(0.7f, 0.0f, std::sqrt(1.0f - 0.49f)), l = glm::normalize(Vec3(20, 0, 5) - p);
  const float t = 0.5f * (1.0f + glm::dot(p, l));
  const Vec3 cool = Vec3(0, 0, 0.4f) + 0.2f * Vec3(0.5f), warm = Vec3(0.4f, 0.4f, 0) + 0.6f * Vec3(0.5f);
  const Vec3 want = t * warm + (1.0f - t) * cool;
  EXPECT_NEAR(lit.x, want.x, 1e-3f);
  EXPECT_NEAR(lit.z, want.z, 1e-3f);
}

TEST(ShaderPlugin, BricksShowMortarAndBricksAndAreSeenInAMirror) {
  const std::string wall = R"({"type":"box","min":[-4,-4,-1],"max":[4,4,0],"material":"m"})";
  auto s = parse(R"("m":{"shader":"bricks","params":{"width":1,"height":0.5,"joint":0.2,"variation":0}},
                    "mirror":{"class":"metal","ks":1,"phong_exponent":0})",
                 wall, R"("settings":{"shadows":"hard"},)");
  ASSERT_TRUE(s) << s.error().message;
  // Facing the wall (+z face): along a row, both the brick colour (red) and mortar (grey) appear.
  int brick = 0, mortar = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 c = radiance_along(**s, Vec3(-2.0f + 0.02f * float(i), 0.25f, 5), Vec3(0, 0, -1));
    if (c.x > 1.8f * c.z) ++brick;
    else if (std::abs(c.x - c.z) < 0.2f * c.x) ++mortar;
  }
  EXPECT_GT(brick, 100);
  EXPECT_GT(mortar, 10);
  // Path tracing reads it as diffuse with its albedo: finite, non-black.
  auto p = parse(R"("m":{"shader":"bricks"})", wall, R"("settings":{"integrator":"path"},)");
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ((*p)->materials[0].cls, MaterialClass::kShader);
  const CameraBasis cam = make_camera_basis((*p)->camera, 32, 32);
  Vec3 sum(0.0f);
  for (int i = 0; i < 64; ++i) {
    const SampleResult r = trace_sample(**p, cam, 16.0f, 16.0f, uint64_t(i));
    ASSERT_TRUE(r.valid);
    sum += r.color;
  }
  EXPECT_GT(sum.x, 0.0f);
  // In a mirror: a metal slab at x = 2 facing -x shows the wall; what a ray sees through it is
  // what the reflected ray sees directly.
  auto m = parse(R"("m":{"shader":"bricks","params":{"variation":0}},"mirror":{"class":"metal","ks":1,"phong_exponent":1e6})",
                 wall + R"(,{"type":"box","min":[2,-4,-1],"max":[2.5,4,4],"material":"mirror"})");
  ASSERT_TRUE(m) << m.error().message;
  int seen = 0;
  for (int i = 0; i < 20; ++i) {
    const float y = -1.0f + 0.1f * float(i);
    const Vec3 via_mirror = radiance_along(**m, Vec3(0.0f, y, 3.0f), Vec3(1, 0, -1));  // meets x = 2 at z = 1
    const Vec3 direct = radiance_along(**m, Vec3(1.999f, y, 1.0f), Vec3(-1, 0, -1));
    EXPECT_LT(glm::length(via_mirror - direct), 1e-3f) << y;
    seen += max_component(direct) > 0.0f;
  }
  EXPECT_EQ(seen, 20);
}

TEST(ShaderPlugin, ToonOutlinesTheSilhouetteAndNanNeverReachesAPixel) {
  auto s = parse(R"("m":{"shader":"toon","params":{"outline":0.3}})", kSphere);
  ASSERT_TRUE(s) << s.error().message;
  const Vec3 edge = radiance_along(**s, Vec3(0.0f, 0.99f, 10), Vec3(0, 0, -1));
  const Vec3 middle = radiance_along(**s, Vec3(0.3f, 0.0f, 10), Vec3(0, 0, -1));
  EXPECT_LT(max_component(edge), 0.05f);
  EXPECT_GT(max_component(middle), 0.2f);
  auto n = parse(R"("m":{"shader":"broken_nan"})", kSphere);
  ASSERT_TRUE(n) << n.error().message;
  const Vec3 c = radiance_along(**n, Vec3(0, 0, 10), Vec3(0, 0, -1));
  EXPECT_TRUE(is_finite(c));
  EXPECT_EQ(c, Vec3(0.0f, 1.0f, 0.0f));  // NaN -> 0, negative -> 0, the finite channel kept
  EXPECT_EQ((*n)->materials[0].kd, Vec3(0.5f));  // no albedo(): 0.5 grey for path tracing
}

// Packets (the static scene traced four rays at a time) give the same pixels as single rays.
TEST(ShaderPlugin, PacketsAndSingleRaysAgree) {
  auto s = parse(R"("m":{"shader":"gooch"},"t":{"shader":"toon"})",
                 std::string(kSphere) + R"(,{"type":"sphere","center":[2.2,0,0],"radius":1,"material":"t"})");
  ASSERT_TRUE(s) << s.error().message;
  const CameraBasis cam = make_camera_basis((*s)->camera, 64, 64);
  float px[64], py[64];
  for (int i = 0; i < 64; ++i) px[i] = 22.0f + float(i % 8) * 3.1f, py[i] = 22.0f + float(i / 8) * 2.7f;
  Hit hits[64];
  primary_hits(**s, cam, 64, px, py, hits);
  int on_plugin = 0;
  for (int i = 0; i < 64; ++i) {
    const SampleResult a = trace_sample(**s, cam, px[i], py[i], 7 + i);
    const SampleResult b = trace_sample(**s, cam, px[i], py[i], 7 + i, nullptr, &hits[i]);
    ASSERT_EQ(a.color, b.color) << i;
    on_plugin += a.depth < kInfinity;
  }
  EXPECT_GT(on_plugin, 20);
}

TEST(ShaderPlugin, BadShadersAndParametersAreOneLine) {
  struct Case {
    std::string material, says;
  };
  const std::vector<Case> cases = {
      {R"({"shader":"granite"})", "materials.m.shader: shader 'granite': no granite.so or libgranite.so in the shader path ("},
      {R"({"shader":"../etc/passwd"})", "a name is letters, digits"},
      {R"({"shader":"broken_version"})", "built for shader interface version 99, frameless has version 1"},
      {R"({"shader":"broken_params"})", "parameter 'k' has a bad range"},
      {R"({"shader":"broken_no_entry"})", "not a frameless shader (no frameless_shader_v1 entry point)"},
      {R"({"shader":"gooch","params":{"kd":[0.5,0.5]}})", "materials.m.params.kd: expected [r, g, b] or one number"},
      {R"({"shader":"gooch","params":{"shine":3}})", "materials.m.params.shine: unknown parameter of shader 'gooch' (it declares kd, blue, yellow, alpha, beta, shininess)"},
      {R"({"shader":"gooch","params":{"blue":2}})", "materials.m.params.blue"},
      {R"({"shader":"gooch","class":"diffuse"})", "class"},
      {R"({"shader":"broken_half_bsdf"})", "only one of eval() and sample()"},
      {R"({"shader":"marble","params":{"tint":"nope"}})", "materials.m.params.tint: unknown texture 'nope'"},
  };
  for (const Case& c : cases) {
    auto s = parse(R"("m":)" + c.material, kSphere);
    ASSERT_FALSE(s) << c.material;
    const std::string& m = s.error().message;
    EXPECT_NE(m.find(c.says), std::string::npos) << m;
    EXPECT_EQ(m.find_first_of("\n\r"), std::string::npos) << m;
  }
  // FRAMELESS_SHADER_PATH is searched too.
  set_shader_search_path({});
  setenv("FRAMELESS_SHADER_PATH", "/nonexistent-a:" FRAMELESS_SHADER_DIR, 1);
  auto l = load_shader("toon", "");
  unsetenv("FRAMELESS_SHADER_PATH");
  ASSERT_TRUE(l) << l.error().message;
  EXPECT_EQ(std::string(l->shader->name), "toon");
}

}  // namespace
}  // namespace frameless
