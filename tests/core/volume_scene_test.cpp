// Volumes in scenes (core/scene/volume_object.h, scene_volumes.h): isosurfaces are surfaces for
// every ray and integrator (hit distance, outward normals, packets equal single rays), the volume
// shader's volumes cast transparent shadows of Beer's law in Whitted and path tracing, and every
// bad "volume" field is a one-line error naming it.
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <tuple>

#include "core/io/scene_json.h"
#include "core/scene/scene_intersect.h"
#include "core/scenes/scene_load.h"
#include "core/shading/direct_light.h"
#include "core/shading/path_tracer.h"
#include "core/shading/render_sample.h"
#include "core/shading/shading.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;

fs::path dir() {
  static const fs::path d = [] {
    const fs::path p = fs::temp_directory_path() / ("frameless_volscene_" + std::to_string(::getpid()));
    fs::create_directories(p);
    return p;
  }();
  return d;
}

Result<std::unique_ptr<Scene>> parse(const std::string& objects, const std::string& extra = "") {
  return parse_scene_json(R"({"camera":{"eye":[0,0,10],"look":[0,0,0]},"ambient":{"type":"none"},)" + extra +
                              R"("materials":{"m":{"class":"diffuse","kd":0.5},"g":{"class":"diffuse","kd":0.8}},"objects":[)" +
                              objects + "]}",
                          (dir() / "s.json").string(), dir().string());
}

Ray ray_from(const Vec3& o, const Vec3& d) {
  Ray r;
  r.org = o;
  r.dir = glm::normalize(d);
  return r;
}

// A 32^3 distance field (voxel spacing 1, centre 15.5), radius-10 sphere, moved to the origin.
constexpr const char* kSphere =
    R"({"type":"volume","file":"volume:sphere:32","isovalue":10,"inside":"below","material":"m",
        "transform":{"translate":[-15.5,-15.5,-15.5]}})";

TEST(VolumeScene, IsosurfaceIsASurfaceWithOutwardNormals) {
  auto s = parse(kSphere);
  ASSERT_TRUE(s) << s.error().message;
  const Scene& scene = **s;
  ASSERT_EQ(scene.volumes.size(), 1u);
  for (const Vec3& d : {Vec3(0, 0, -1), Vec3(0.2f, 0.1f, -1), Vec3(-0.3f, 0.05f, -1)}) {
    const Ray r = ray_from(Vec3(0, 0, 30), d);
    Hit hit;
    ASSERT_TRUE(scene_intersect(scene, nullptr, r, hit));
    const SurfacePoint sp = scene_surface_point(scene, nullptr, r, hit);
    // The trilinear sphere of radius 10 voxels: within a tenth of a voxel of the true sphere.
    EXPECT_NEAR(glm::length(sp.p), 10.0f, 0.1f);
    EXPECT_TRUE(sp.front_face);
    EXPECT_GT(glm::dot(sp.ng, glm::normalize(sp.p)), 0.99f);  // out of the inside (below 10)
    Ray shadow = ray_from(sp.p + sp.ng * 1e-3f, Vec3(0, 0, -1));
    shadow.tmax = 100.0f;
    EXPECT_TRUE(scene_occluded(scene, nullptr, shadow));  // isosurfaces block shadow rays
  }
  // Inside "above" flips the normal: the same surface then faces inwards.
  std::string flipped = kSphere;
  flipped.replace(flipped.find("below"), 5, "above");
  auto f = parse(flipped);
  ASSERT_TRUE(f);
  const Ray r = ray_from(Vec3(0, 0, 30), Vec3(0, 0, -1));
  Hit hit;
  ASSERT_TRUE(scene_intersect(**f, nullptr, r, hit));
  EXPECT_FALSE(scene_surface_point(**f, nullptr, r, hit).front_face);
}

TEST(VolumeScene, PacketsAndSingleRaysAgreeUnderEveryIntegrator) {
  for (const char* integrator : {"whitted", "path", "igi"}) {
    auto s = parse(std::string(kSphere) + R"(,{"type":"plane","point":[0,-12,0],"normal":[0,1,0],"size":60,"material":"g"})",
                   std::string(R"("settings":{"integrator":")") + integrator +
                       R"("},"lights":[{"type":"point","position":[5,30,20]}],)");
    ASSERT_TRUE(s) << s.error().message;
    const Scene& scene = **s;
    const CameraBasis cam = make_camera_basis(scene.camera, 64, 64);
    float px[64], py[64];
    for (int i = 0; i < 64; ++i) px[i] = 10.0f + float(i % 8) * 5.3f, py[i] = 8.0f + float(i / 8) * 6.1f;
    Hit hits[64];
    primary_hits(scene, cam, 64, px, py, hits);
    int on_volume = 0;
    for (int i = 0; i < 64; ++i) {
      const SampleResult a = trace_sample(scene, cam, px[i], py[i], 99 + i);
      const SampleResult b = trace_sample(scene, cam, px[i], py[i], 99 + i, nullptr, &hits[i]);
      ASSERT_TRUE(a.valid) << integrator;
      EXPECT_EQ(a.color, b.color) << integrator << " sample " << i;
      EXPECT_EQ(a.depth, b.depth);
      on_volume += a.depth < 25.0f;
    }
    EXPECT_GT(on_volume, 10) << integrator;
  }
}

// A raw 8^3 float volume of constant 1 (its values through a transfer function of opacity a per voxel).
std::string constant_raw() {
  const std::string path = (dir() / "block.raw").string();
  std::vector<float> v(8 * 8 * 8, 1.0f);
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * 4));
  return path;
}

TEST(VolumeScene, VolumeShaderCastsBeersLawShadowsInWhittedAndPathTracing) {
  const std::string raw = constant_raw();
  // A 7-voxel block (voxel spacing 0.5: 3.5 units thick) above a floor, a point light above it.
  const std::string block = R"({"type":"volume","file":")" + raw +
                            R"(","dims":[8,8,8],"format":"float32","spacing":0.5,"mode":"direct","shade":false,
      "transfer":[{"value":0,"color":[1,1,1],"opacity":0.2},{"value":2,"color":[1,1,1],"opacity":0.2}],
      "transform":{"translate":[-1.75,2,-1.75]}},
     {"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":40,"material":"g"})";
  for (const char* integrator : {"whitted", "path"}) {
    auto s = parse(block, std::string(R"("settings":{"integrator":")") + integrator +
                              R"(","shadows":"hard"},"lights":[{"type":"point","position":[0,20,0]}],)");
    ASSERT_TRUE(s) << s.error().message;
    const Scene& scene = **s;
    EXPECT_TRUE(scene.see_through_volumes);
    // The floor right below the block, seen from the side (the camera ray misses the block),
    // against a floor point the block does not shadow.
    const Ray under = ray_from(Vec3(6, 1, 0), Vec3(-6, -1, 0)), open = ray_from(Vec3(12, 1, 0), Vec3(-6, -1, 0));
    // Direct light only (a point light: next-event estimation is exact, no noise).
    PathOptions o;
    o.max_bounces = 1;
    const bool path = std::string(integrator) == "path";
    const Vec3 a = path ? trace_path(scene, under, 5, nullptr, nullptr, nullptr, nullptr, nullptr, o)
                        : trace_radiance(scene, under, 0, Vec3(1.0f), nullptr);
    const Vec3 b = path ? trace_path(scene, open, 5, nullptr, nullptr, nullptr, nullptr, nullptr, o)
                        : trace_radiance(scene, open, 0, Vec3(1.0f), nullptr);
    // exp(-sigma d) with sigma = -ln(1 - 0.2) per voxel and d = 7 voxels; the two floor points
    // see the light at different angles (Parker's point lights give irradiance pi l_e cos at any
    // distance: the cosines' ratio corrects for it).
    const float expect = std::pow(0.8f, 7.0f);
    const Vec3 pu = Vec3(0, 0, 0), po = Vec3(6, 0, 0), l(0, 20, 0);
    const float geometry = glm::normalize(l - pu).y / glm::normalize(l - po).y;
    ASSERT_GT(b.x, 0.0f) << integrator;
    EXPECT_NEAR(a.x / (b.x * geometry), expect, 2e-3f) << integrator;
  }
}

TEST(VolumeScene, IsosurfacesCastPenumbraeUnderSoftShadows) {
  // The sphere (radius 10) above a floor, a big spherical light above: Parker's soft shadows.
  const std::string floor = R"(,{"type":"plane","point":[0,-15,0],"normal":[0,1,0],"size":200,"material":"g"})";
  const std::string light = R"("settings":{"shadows":"soft"},"lights":[{"type":"spherical","position":[0,40,0],"radius":8}],)";
  auto with = parse(std::string(kSphere) + floor, light), without = parse(floor.substr(1), light);
  ASSERT_TRUE(with && without) << (with ? without.error().message : with.error().message);
  int umbra = 0, penumbra = 0, lit = 0;
  for (float x = 0.0f; x <= 30.0f; x += 0.5f) {
    const Ray down = ray_from(Vec3(x, 0, 30), Vec3(0, -15, -30));  // hits the floor at (x, -15, 0)
    const float a = trace_radiance(**with, down, 0, Vec3(1.0f), nullptr).x;
    const float b = trace_radiance(**without, down, 0, Vec3(1.0f), nullptr).x;
    ASSERT_GT(b, 0.0f);
    const float v = a / b;  // the light's visible share
    umbra += v < 0.02f;
    penumbra += v > 0.05f && v < 0.95f;
    lit += v > 0.98f;
  }
  EXPECT_GT(umbra, 0);
  EXPECT_GT(penumbra, 1);  // more than one step between shadow and light: a penumbra
  EXPECT_GT(lit, 0);
}

TEST(VolumeScene, BadVolumeFieldsGiveOneLineErrors) {
  const std::string raw = constant_raw(), vdb = std::string(FRAMELESS_TEST_DATA) + "/volumes/fog_blosc.vdb";
  struct Case {
    std::string object, field, says;
  };
  const std::vector<Case> cases = {
      {R"({"type":"volume","file":"volume:sphere:8","isovalue":2})", "objects[0].material", "missing"},
      {R"({"type":"volume","file":"volume:sphere:8","isovalue":2,"material":"nope"})", "objects[0].material", "unknown material"},
      {R"({"type":"volume","file":"volume:sphere:8","isovalue":[1,2],"material":["m"]})", "objects[0].material", "one material per isovalue"},
      {R"({"type":"volume","file":"volume:sphere:8","mode":"mri"})", "objects[0].mode", "expected isosurface, direct or mip"},
      {R"({"type":"volume","file":"volume:sphere:8","mode":"isosurface","material":"m"})", "objects[0].isovalue", "missing"},
      {R"({"type":"volume","file":"volume:sphere:8","isovalue":2,"material":"m","transfer":"hot"})", "objects[0].transfer", "only for the direct and mip"},
      {R"({"type":"volume","file":"volume:sphere:8","transfer":"rainbow"})", "objects[0].transfer", "unknown transfer function preset"},
      {R"({"type":"volume","file":"volume:sphere:8","transfer":[{"value":2,"opacity":0.1},{"value":1,"opacity":0.1}]})", "objects[0].transfer", "increase strictly"},
      {R"({"type":"volume","file":"volume:sphere:8","transfer":[{"value":0,"opacity":0.1},{"value":1,"opacity":2}]})", "objects[0].transfer[1].opacity", "in [0, 1]"},
      {R"({"type":"volume","file":"volume:sphere:8","sampling_rate":0})", "objects[0].sampling_rate", "samples per voxel"},
      {R"({"type":"volume","file":"volume:torus:8"})", "objects[0].file", "unknown kind"},
      {R"({"type":"volume","file":"head.vdb"})", "objects[0].file", "head.vdb: cannot open"},
      {R"({"type":"volume","file":")" + vdb + R"(","grid":"pressure"})", "objects[0].file", "no grid named 'pressure'"},
      {R"({"type":"volume","file":")" + vdb + R"(","spacing":2})", "objects[0].spacing", "their map gives it"},
      {R"({"type":"volume","file":"volume:sphere:8","grid":"density"})", "objects[0].grid", "only for OpenVDB files"},
      {R"({"type":"volume","file":")" + raw + R"("})", "objects[0].dims", "missing"},
      {R"({"type":"volume","file":")" + raw + R"(","dims":[8,8,9],"format":"float32"})", "objects[0].file", "block.raw"},
      {R"({"type":"volume","file":")" + raw + R"(","dims":[8,8,8],"format":"int7"})", "objects[0].format", "expected uint8, uint16 or float32"},
      {R"({"type":"volume","file":"volume:sphere:8","dims":[8,8,8]})", "objects[0].dims", "only for raw files"},
      {R"({"type":"volume","file":"volume:sphere:8","isovalue":2,"material":"m","inside":"left"})", "objects[0].inside", "above or below"},
      {R"({"type":"volume","file":"volume:sphere:8","isovalue":2,"material":"m","transform":{"scale":0}})", "objects[0].transform", "non-zero"},
      {R"({"type":"volume","file":"volume:sphere:8","colour":1})", "objects[0]", "colour"},
  };
  for (const Case& c : cases) {
    auto s = parse(c.object);
    ASSERT_FALSE(s) << c.object;
    const std::string& m = s.error().message;
    EXPECT_NE(m.find(c.field), std::string::npos) << m;
    EXPECT_NE(m.find(c.says), std::string::npos) << m;
    EXPECT_EQ(m.find_first_of("\n\r"), std::string::npos) << m;
  }
}

// OpenVDB level sets are isosurfaces at 0 with the inside below, placed by the file's map (voxels
// of 0.5) and then the object's transform; fog volumes go to the volume shader.
TEST(VolumeScene, OpenVdbGridsArePlacedByTheirMaps) {
  const std::string data = std::string(FRAMELESS_TEST_DATA) + "/volumes/";
  auto s = parse(R"({"type":"volume","file":")" + data + R"(sphere_ls_zip.vdb","material":"m","transform":{"translate":[0,0,-10]}},
                    {"type":"volume","file":")" + data + R"(fog_zip.vdb","grid":"density"})");
  ASSERT_TRUE(s) << s.error().message;
  const Scene& scene = **s;
  ASSERT_EQ(scene.volumes.size(), 2u);
  EXPECT_EQ(scene.volumes[0].mode, VolumeMode::kIsosurface);
  EXPECT_EQ(scene.volumes[0].isovalues, std::vector<float>{0.0f});
  EXPECT_FALSE(scene.volumes[0].inside_above);
  EXPECT_EQ(scene.volumes[1].mode, VolumeMode::kDirect);
  // The sphere of radius 3 at (6, 5.5, 6.25 - 10): hit from +z and -x, outward normals.
  for (const auto& [o, d, want] : {std::tuple{Vec3(6, 5.5f, 20), Vec3(0, 0, -1), Vec3(6, 5.5f, -0.75f)},
                                   std::tuple{Vec3(-9, 5.5f, -3.75f), Vec3(1, 0, 0), Vec3(3, 5.5f, -3.75f)}}) {
    const Ray r = ray_from(o, d);
    Hit hit;
    ASSERT_TRUE(scene_intersect(scene, nullptr, r, hit));
    const SurfacePoint sp = scene_surface_point(scene, nullptr, r, hit);
    EXPECT_LT(glm::distance(sp.p, want), 0.05f) << sp.p.x << " " << sp.p.y << " " << sp.p.z;
    EXPECT_GT(glm::dot(sp.ng, -d), 0.95f);
  }
}

TEST(VolumeScene, BuiltInVolumeScenesLoadInEveryMode) {
  for (const char* name : {"volume:sphere:16", "volume:marschner-lobb:17:direct", "volume:shepp-logan:24:mip",
                           "volume:shepp-logan:20x24x28"}) {
    auto s = load_scene(name);
    ASSERT_TRUE(s) << name << ": " << s.error().message;
    EXPECT_EQ((*s)->volumes.size(), 1u);
  }
  auto bad = load_scene("volume:sphere:16:xray");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find(":direct or :mip"), std::string::npos) << bad.error().message;
}

}  // namespace
}  // namespace frameless
