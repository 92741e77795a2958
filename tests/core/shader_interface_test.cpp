// The rest of the plug-in interface (include/frameless/shader.h): texture parameters name the
// scene's textures and the host looks them up, the hit carries a tangent frame that follows the
// UVs, and a shader's own BSDF (eval/sample) is what path tracing sees, where a shader without
// one is read as its albedo.
#include <gtest/gtest.h>

#include <cmath>

#include "core/io/scene_json.h"
#include "core/io/shader_library.h"
#include "core/scene/scene_intersect.h"
#include "core/shading/path_tracer.h"
#include "core/shading/plugin_hit.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

Result<std::unique_ptr<Scene>> parse(const std::string& body) {
  set_shader_search_path({FRAMELESS_SHADER_DIR});
  return parse_scene_json("{" + body + "}", "/nonexistent/s.json", "/nonexistent");
}

constexpr const char* kFloor = R"("objects":[{"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":40,"material":"m"}])";
constexpr const char* kLight = R"("ambient":{"type":"none"},"lights":[{"type":"point","position":[0,6,0],"color":1}],)";

Vec3 down_at(const Scene& s, float x) { return testing::radiance_along(s, Vec3(x, 3.0f, 0.3f), Vec3(0, -1, 0)); }

TEST(ShaderInterface, TextureParametersAreLookedUpThroughTheHost) {
  const std::string textures = R"("textures":{"half":{"type":"checker","color_a":[0.5,0.5,0.5],"color_b":[0.5,0.5,0.5]}},)";
  auto plain = parse(std::string(kLight) + textures + R"("materials":{"m":{"shader":"marble","params":{"polish":0}}},)" + kFloor);
  auto tinted = parse(std::string(kLight) + textures + R"("materials":{"m":{"shader":"marble","params":{"polish":0,"tint":"half"}}},)" + kFloor);
  ASSERT_TRUE(plain) << plain.error().message;
  ASSERT_TRUE(tinted) << tinted.error().message;
  float lo = 1e9f, hi = 0.0f;
  for (int i = 0; i < 40; ++i) {
    const float x = -1.0f + 0.05f * float(i);
    const Vec3 a = down_at(**plain, x), b = down_at(**tinted, x);
    ASSERT_GT(a.x, 0.0f);
    EXPECT_NEAR(b.x, 0.5f * a.x, 1e-4f * a.x + 1e-6f) << x;
    lo = std::min(lo, a.x), hi = std::max(hi, a.x);
  }
  EXPECT_GT(hi, 1.5f * lo) << "veins and stone both appear";
}

TEST(ShaderInterface, TheHitsTangentFrameFollowsTheUvs) {
  // A quad in z = 0 whose u runs along -x and v along +y (mirrored against the usual layout).
  auto s = parse(R"("materials":{"m":{"shader":"toon"}},"objects":[{"type":"triangles",
      "vertices":[[-1,-1,0],[1,-1,0],[1,1,0],[-1,1,0]],"uvs":[[1,0],[0,0],[0,1],[1,1]],
      "indices":[[0,1,2],[0,2,3]],"material":"m"}])");
  ASSERT_TRUE(s) << s.error().message;
  Ray r;
  r.org = Vec3(0.2f, 0.1f, 5.0f);
  r.dir = Vec3(0, 0, -1);
  Hit hit;
  ASSERT_TRUE(scene_intersect(**s, nullptr, r, hit));
  const SurfacePoint sp = scene_surface_point(**s, nullptr, r, hit);
  const fl_hit h = make_plugin_hit(**s, r, hit, sp, 0);
  EXPECT_NEAR(h.tangent.x, -1.0f, 1e-5f);
  EXPECT_NEAR(h.u, 0.4f, 1e-5f);
  EXPECT_NEAR(h.v, 0.55f, 1e-5f);
  // The bitangent runs along increasing v (+y) although the layout is mirrored.
  EXPECT_NEAR(h.bitangent.y, 1.0f, 1e-5f);
  EXPECT_NEAR(h.shading_normal.z, 1.0f, 1e-5f);
}

// Path-traced radiance over Whitted's at point x of the floor (64 paths).
double path_over_whitted(const Scene& path, const Scene& whitted, float x) {
  Ray r;
  r.org = Vec3(x, 3.0f, 0.3f);
  r.dir = Vec3(0, -1, 0);
  Vec3 sum(0.0f);
  for (int k = 0; k < 64; ++k) sum += trace_path(path, r, uint64_t(1000 + k));
  return double(sum.x / 64.0f) / double(down_at(whitted, x).x);
}

TEST(ShaderInterface, PathTracingSeesTheShadersOwnBsdf) {
  const auto pair = [](const std::string& material) {
    auto p = parse(std::string(kLight) + R"("settings":{"integrator":"path","max_depth":1},"materials":{"m":)" + material + "}," + kFloor);
    auto w = parse(std::string(kLight) + R"("materials":{"m":)" + material + "}," + kFloor);
    EXPECT_TRUE(p && w);
    return std::make_pair(std::move(*p), std::move(*w));
  };
  // Wood has eval/sample: path tracing shows its rings as Whitted does (the same ratio everywhere).
  auto wood = pair(R"({"shader":"wood","params":{"varnish":0,"rings":3}})");
  ASSERT_TRUE(wood.first->shaders[0].shader->eval);
  // Bricks has none: path tracing sees one albedo, so bricks and mortar differ from Whitted's.
  auto bricks = pair(R"({"shader":"bricks","params":{"variation":0,"width":0.5,"height":0.2,"joint":0.3}})");
  double wood_lo = 1e9, wood_hi = 0, bricks_lo = 1e9, bricks_hi = 0;
  for (int i = 0; i < 24; ++i) {
    const float x = -0.6f + 0.05f * float(i);
    const double w = path_over_whitted(*wood.first, *wood.second, x);
    const double b = path_over_whitted(*bricks.first, *bricks.second, x);
    wood_lo = std::min(wood_lo, w), wood_hi = std::max(wood_hi, w);
    bricks_lo = std::min(bricks_lo, b), bricks_hi = std::max(bricks_hi, b);
  }
  EXPECT_LT(wood_hi / wood_lo, 1.02) << wood_lo << " " << wood_hi;
  EXPECT_GT(bricks_hi / bricks_lo, 1.2) << bricks_lo << " " << bricks_hi;
}

}  // namespace
}  // namespace frameless
