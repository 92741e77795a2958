// Textures at hits: texture coordinates, textured colours, cut-outs for camera and shadow rays
// (leaf-shaped shadows), normal maps, and JSON texture input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scene/texturing.h"
#include "core/scenes/scene_load.h"
#include "core/shading/render_sample.h"
#include "core/shading/soft_shadow.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

// A w x h single-channel-plus-alpha image: alpha 255 where mask(x, y), else 0 (row 0 on top).
template <class F>
std::shared_ptr<const Image> alpha_image(int w, int h, F mask) {
  auto img = std::make_shared<Image>();
  img->width = w;
  img->height = h;
  img->channels = 2;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      img->ldr.push_back(200);
      img->ldr.push_back(mask(x, y) ? 255 : 0);
    }
  return img;
}

// A horizontal unit-UV quad at height y covering [-1, 1]^2 in x and z, with material m.
void add_uv_quad(Scene& s, float y, uint16_t m) {
  MeshData q;
  q.positions = {Vec3(-1, y, -1), Vec3(-1, y, 1), Vec3(1, y, 1), Vec3(1, y, -1)};
  // u grows with x, v grows with -z (the image's top row is at z = -1).
  q.uvs = {Vec2(0, 1), Vec2(0, 0), Vec2(1, 0), Vec2(1, 1)};
  q.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
  add_mesh(s, q, glm::mat4(1.0f), m, true);
}

TEST(Texturing, TriangleAndSphereCoordinates) {
  auto s = testing::make_empty_scene();
  s->materials.push_back(Material{});
  add_uv_quad(*s, 0.0f, 0);
  testing::add_sphere(s->geometry, Vec3(0, 5, 0), 1.0f, 0);
  finalize_scene(*s);
  Ray down;
  down.org = Vec3(0.5f, 1.0f, -0.5f);
  down.dir = Vec3(0, -1, 0);
  Hit h;
  ASSERT_TRUE(s->accel.intersect(down, h));
  const Vec2 uv = hit_uv(s->geometry, down, h);
  EXPECT_NEAR(uv.x, 0.75f, 1e-5f);
  EXPECT_NEAR(uv.y, 0.75f, 1e-5f);
  // Sphere: the north pole is v = 1, a point on the +x equator is u = 0.5, v = 0.5.
  Ray up;
  up.org = Vec3(0, 2, 0);
  up.dir = Vec3(0, 1, 0);
  ASSERT_TRUE(s->accel.intersect(up, h));
  EXPECT_NEAR(hit_uv(s->geometry, up, h).y, 0.0f, 1e-4f);  // hits the south pole from below
  Ray side;
  side.org = Vec3(3, 5, 0);
  side.dir = Vec3(-1, 0, 0);
  ASSERT_TRUE(s->accel.intersect(side, h));
  EXPECT_NEAR(hit_uv(s->geometry, side, h).x, 0.5f, 1e-4f);
  EXPECT_NEAR(hit_uv(s->geometry, side, h).y, 0.5f, 1e-4f);
}

TEST(Texturing, CutoutIsAbsentForCameraAndShadowRays) {
  auto s = testing::make_empty_scene();
  Material leaf;
  leaf.kd = Vec3(1.0f);
  Material ground;
  ground.kd = Vec3(1.0f);
  s->materials = {leaf, ground};
  // Left half of the image opaque, right half transparent.
  Texture t;
  t.image = alpha_image(16, 16, [](int x, int) { return x < 8; });
  t.srgb = false;
  t.wrap = TextureWrap::kClamp;
  s->textures.push_back(t);
  s->materials[0].alpha_tex = 0;
  add_uv_quad(*s, 2.0f, 0);
  testing::add_horizontal_quad(s->geometry, 0.0f, 10.0f, 1);
  s->lights.push_back(Light{Vec3(0, 10, 0), Vec3(1.0f), 0.0f});
  s->settings.shadows = ShadowMode::kHard;
  finalize_scene(*s);
  ASSERT_TRUE(s->features.has_cutouts);
  Ray down;
  down.dir = Vec3(0, -1, 0);
  Hit h;
  // Over the opaque half the leaf is hit; over the transparent half the ray reaches the ground.
  down.org = Vec3(-0.5f, 5, 0);
  ASSERT_TRUE(s->accel.intersect(down, h));
  EXPECT_NEAR(h.t, 3.0f, 1e-4f);
  down.org = Vec3(0.5f, 5, 0);
  ASSERT_TRUE(s->accel.intersect(down, h));
  EXPECT_NEAR(h.t, 5.0f, 1e-4f);
  // Shadow rays: the ground is dark under the opaque half only (a leaf-shaped shadow).
  Ray shadow;
  shadow.dir = Vec3(0, 1, 0);
  shadow.tmax = 9.0f;
  shadow.org = Vec3(-0.5f, 0.001f, 0);
  EXPECT_TRUE(s->accel.occluded(shadow));
  shadow.org = Vec3(0.5f, 0.001f, 0);
  EXPECT_FALSE(s->accel.occluded(shadow));
  // Soft shadows give cut-outs their hard texel shadow, and let the transparent texels through.
  s->lights[0].radius = 0.5f;
  set_shadow_settings(*s, ShadowMode::kSoft, 16, false);
  ShadowQuery q;
  q.dir = Vec3(0, 1, 0);
  q.tmax = 9.0f;
  q.half_angle = std::asin(0.05f);
  q.tan_half = std::tan(q.half_angle);
  q.org = Vec3(-0.5f, 0.001f, 0);
  EXPECT_EQ(soft_visibility(*s, q), 0.0f);
  q.org = Vec3(0.5f, 0.001f, 0);
  EXPECT_EQ(soft_visibility(*s, q), 1.0f);
}

TEST(Texturing, TexturedColourMultipliesKd) {
  auto s = testing::make_empty_scene();
  Material m;
  m.kd = Vec3(0.5f);
  Texture checker;
  checker.kind = TextureKind::kChecker;
  checker.color_a = Vec3(1.0f, 0.0f, 0.0f);
  checker.color_b = Vec3(0.0f, 0.0f, 1.0f);
  checker.frequency = 1.0f;
  s->textures.push_back(checker);
  m.kd_tex = 0;
  s->materials.push_back(m);
  testing::add_horizontal_quad(s->geometry, 0.0f, 10.0f, 0);
  s->ambient.kind = AmbientKind::kConstant;
  s->ambient.constant = Vec3(1.0f);
  finalize_scene(*s);
  s->camera.eye = Vec3(0.25f, 5.0f, 0.25f);
  s->camera.look = Vec3(0.25f, 0.0f, 0.2501f);
  s->camera.up = Vec3(0, 0, -1);
  const CameraBasis cam = make_camera_basis(s->camera, 1, 1);
  // (0.25, 0, 0.25): floor parities 0 + 0 + 0: color_a; k_d l_a = 0.5 * red.
  const Vec3 c = render_sample(*s, cam, 0, 0, 0, false).color;
  EXPECT_NEAR(c.x, 0.5f, 1e-4f);
  EXPECT_NEAR(c.z, 0.0f, 1e-4f);
  s->camera.eye.x = s->camera.look.x = 1.25f;
  const Vec3 d = render_sample(*s, make_camera_basis(s->camera, 1, 1), 0, 0, 0, false).color;
  EXPECT_NEAR(d.x, 0.0f, 1e-4f);
  EXPECT_NEAR(d.z, 0.5f, 1e-4f);
}

TEST(Texturing, NormalMapTiltsTheShadingNormal) {
  auto s = testing::make_empty_scene();
  Material m;
  auto img = std::make_shared<Image>();
  img->width = img->height = 1;
  img->channels = 3;
  // Tangent-space (0.6, 0, 0.8): encoded as (0.8, 0.5, 0.9) in [0, 1].
  img->ldr = {204, 128, 230};
  Texture t;
  t.image = img;
  t.srgb = false;
  s->textures.push_back(t);
  m.normal_tex = 0;
  s->materials.push_back(m);
  add_uv_quad(*s, 0.0f, 0);
  finalize_scene(*s);
  Ray down;
  down.org = Vec3(0.2f, 1.0f, 0.1f);
  down.dir = Vec3(0, -1, 0);
  Hit h;
  ASSERT_TRUE(s->accel.intersect(down, h));
  SurfacePoint sp = surface_point(s->geometry, down, h);
  MaterialParams p = s->materials[0];
  apply_textures(*s, down, h, p, sp);
  // u grows along +x on this quad, so the normal tilts toward +x by about 37 degrees.
  EXPECT_NEAR(sp.ns.x, 0.6f, 0.02f);
  EXPECT_NEAR(sp.ns.y, 0.8f, 0.02f);
  EXPECT_NEAR(glm::length(sp.ns), 1.0f, 1e-5f);
  EXPECT_EQ(sp.ng, Vec3(0, 1, 0));
}

TEST(Texturing, JsonTexturesAndTheirErrors) {
  const std::string dir = ::testing::TempDir() + "/frameless_json_textures";
  std::filesystem::create_directories(dir);
  auto parse = [&](const std::string& textures, const std::string& material) {
    const std::string text = R"({"textures": )" + textures + R"(, "materials": {"m": )" + material +
                             R"(}, "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1,
                             "material": "m"}]})";
    return parse_scene_json(text, "t.json", dir);
  };
  auto ok = parse(R"({"marble": {"type": "marble", "frequency": 2, "transform": {"scale": 2}}})",
                  R"({"class": "diffuse", "kd_texture": "marble"})");
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_TRUE(ok.value()->features.has_textures);
  EXPECT_EQ(ok.value()->textures.size(), 1u);
  EXPECT_EQ(ok.value()->textures[0].kind, TextureKind::kMarble);
  // Each broken input names its field, on one line.
  const std::pair<std::string, std::string> bad[] = {
      {R"({"x": {"type": "velvet"}})", "textures.x.type"},
      {R"({"x": {"type": "vel\nvet\r"}})", "'vel\\nvet\\r'"},  // quoted input stays on one line
      {R"({"x": {"type": "image", "file": "missing.png"}})", "textures.x.file"},
      {R"({"x": {"type": "marble", "octaves": 99}})", "textures.x.octaves"},
      {R"({"x": {"type": "image", "file": "missing.png", "wrap": "mirror"}})", "textures.x"},
  };
  for (const auto& [textures, field] : bad) {
    auto r = parse(textures, R"({"class": "diffuse"})");
    ASSERT_FALSE(r.ok()) << textures;
    EXPECT_NE(r.error().message.find(field), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
  }
  auto unknown = parse("{}", R"({"class": "diffuse", "kd_texture": "nope"})");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("materials.m.kd_texture: unknown texture 'nope'"),
            std::string::npos)
      << unknown.error().message;
}

TEST(Texturing, ObjectSpaceSolidTexturesMoveWithTheirObject) {
  auto load = [](const char* space) {
    const std::string text = std::string(R"({"textures": {"m": {"type": "marble", "space": ")") +
                             space + R"("}}, "materials": {"s": {"class": "diffuse", "kd": 1,
      "kd_texture": "m"}}, "objects": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "s"},
      {"type": "sphere", "center": [7.3, 0, 0], "radius": 1, "material": "s"}]})";
    auto r = parse_scene_json(text, "o.json", "/");
    EXPECT_TRUE(r.ok()) << r.error().message;
    return std::move(r.value());
  };
  // The colour seen at the same spot on each sphere.
  auto colours = [](const Scene& s) {
    std::pair<Vec3, Vec3> c;
    for (int k = 0; k < 2; ++k) {
      Ray r;
      r.org = Vec3(7.3f * float(k) + 0.3f, 0.2f, 5.0f);
      r.dir = Vec3(0, 0, -1);
      Hit h;
      EXPECT_TRUE(s.accel.intersect(r, h));
      SurfacePoint sp = surface_point(s.geometry, r, h);
      MaterialParams m = s.materials[sp.material];
      apply_textures(s, r, h, m, sp);
      (k == 0 ? c.first : c.second) = m.kd;
    }
    return c;
  };
  auto object = load("object");
  const auto [a, b] = colours(*object);
  EXPECT_NEAR(glm::length(a - b), 0.0f, 1e-5f);
  EXPECT_EQ(object->materials.size(), 3u);  // the named material plus one copy per sphere
  auto world = load("world");
  const auto [c, d] = colours(*world);
  EXPECT_GT(glm::length(c - d), 1e-3f);  // in world space the two spots differ
  auto bad = parse_scene_json(R"({"textures": {"m": {"type": "wood", "space": "local"}},
    "objects": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "x"}]})", "o.json", "/");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("textures.m.space"), std::string::npos) << bad.error().message;
}

TEST(Texturing, JsonSceneReferencesAGltfModelWithTransformAndOverride) {
  const std::string model = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
  if (!std::filesystem::exists(model)) GTEST_SKIP() << "assimp-testmodels not installed";
  auto scene = [&](const std::string& extra) {
    const std::string text = R"({"materials": {"red": {"class": "diffuse", "kd": [1, 0, 0]}},
      "objects": [{"type": "mesh", "file": ")" + model + R"(", "transform": {"translate": [10, 0, 0]})" +
                             extra + "}]}";
    return parse_scene_json(text, "m.json", "/");
  };
  auto own = scene("");
  ASSERT_TRUE(own.ok()) << own.error().message;
  const Scene& a = *own.value();
  EXPECT_EQ(a.geometry.num_triangles(), 12u);
  ASSERT_EQ(a.materials.size(), 2u);  // "red", then the model's own
  EXPECT_NE(a.materials[1].kd_tex, kNoTexture);
  for (uint16_t m : a.geometry.triangle_material) EXPECT_EQ(m, 1);
  Vec3 lo, hi;
  geometry_bounds(a.geometry, lo, hi);
  EXPECT_NEAR(0.5f * (lo.x + hi.x), 10.0f, 1e-4f);
  auto over = scene(R"(, "material": "red")");
  ASSERT_TRUE(over.ok()) << over.error().message;
  for (uint16_t m : over.value()->geometry.triangle_material) EXPECT_EQ(m, 0);
  EXPECT_FALSE(over.value()->features.has_textures);
}

TEST(Texturing, ShowcaseSceneLoadsWithEverything) {
  if (!std::filesystem::exists("/usr/share/glmark2/textures") ||
      !std::filesystem::exists("/usr/share/assimp/models"))
    GTEST_SKIP() << "glmark2-data or assimp-testmodels not installed";
  auto s = load_scene("showcase");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const SceneFeatures& f = s.value()->features;
  EXPECT_TRUE(f.has_textures);
  EXPECT_TRUE(f.has_cutouts);
  EXPECT_TRUE(f.has_soft_lights);
  EXPECT_TRUE(f.has_dielectric);
  // Images are shared: the glTF's texture plus the four files the JSON names.
  EXPECT_GE(s.value()->textures.size(), 7u);
}

}  // namespace
}  // namespace frameless
