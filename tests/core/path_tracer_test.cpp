// The path tracer (core/shading/path_tracer.h): white furnaces, each light kind found alike by
// light sampling, BSDF sampling and their MIS combination, one bounce equal to Whitted's
// diffuse term, determinism, and the integrator setting. Statistical checks use fixed seeds and
// accept within 5 standard errors (two-sided significance about 6e-7 each, if the means agree).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/base/rng.h"
#include "core/io/scene_json.h"
#include "core/scenes/scene_load.h"
#include "core/shading/path_tracer.h"
#include "path_estimate.h"
#include "core/shading/render_sample.h"
#include "core/shading/shading.h"

namespace frameless {
namespace {

using testing::estimate;
using testing::Estimate;
using testing::make_ray;

std::unique_ptr<Scene> parse_ok(const std::string& json) {
  auto s = parse_scene_json(json, "t.json", ".");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? std::move(*s) : nullptr;
}

// A white furnace: objects inside a uniform environment of radiance 1, no lights, no ambient.
std::string furnace(const std::string& materials, const std::string& objects) {
  return R"({"settings":{"integrator":"path","background":1,"max_depth":1000},
             "ambient":{"type":"none"},"materials":{)" + materials + R"(},"objects":[)" + objects + "]}";
}

TEST(PathTracer, WhiteFurnaceConvexObjectsOfAlbedoOneVanish) {
  // Lambertian, mirror and clear glass of albedo 1: every ray returns 1.
  for (const char* m : {R"("w":{"class":"diffuse","kd":1})", R"("w":{"class":"metal","ks":1,"phong_exponent":50})",
                        R"("w":{"class":"dielectric","ior":1.5,"kh":0})"}) {
    auto s = parse_ok(furnace(m, R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"w"})"));
    ASSERT_TRUE(s);
    for (const Vec3& dir : {Vec3(0, 0, -1), Vec3(0.25f, 0.1f, -1)}) {
      const Estimate e = estimate(*s, make_ray(Vec3(0, 0, 4), dir), 20000, 7);
      EXPECT_NEAR(e.mean, 1.0, 5.0 * e.se + 1e-4) << m;
    }
  }
}

TEST(PathTracer, WhiteFurnaceConcaveOpenBoxOfAlbedoOne) {
  // Five faces of a cube (open towards the camera): light bounces inside before it leaves.
  const std::string faces =
      R"({"type":"plane","point":[0,0,-1],"normal":[0,0,1],"size":2,"material":"w"},
         {"type":"plane","point":[-1,0,0],"normal":[1,0,0],"size":2,"material":"w"},
         {"type":"plane","point":[1,0,0],"normal":[-1,0,0],"size":2,"material":"w"},
         {"type":"plane","point":[0,-1,0],"normal":[0,1,0],"size":2,"material":"w"},
         {"type":"plane","point":[0,1,0],"normal":[0,-1,0],"size":2,"material":"w"})";
  auto s = parse_ok(furnace(R"("w":{"class":"diffuse","kd":1})", faces));
  ASSERT_TRUE(s);
  // Into the box's back corner and onto a side wall.
  for (const Vec3& dir : {Vec3(-0.3f, -0.3f, -1), Vec3(0.5f, 0.1f, -1)}) {
    const Estimate e = estimate(*s, make_ray(Vec3(0, 0, 3), dir), 40000, 11);
    EXPECT_NEAR(e.mean, 1.0, 5.0 * e.se + 1e-4);
  }
}

TEST(PathTracer, ConvexDiffuseObjectRendersAsItsAlbedo) {
  auto s = parse_ok(furnace(R"("w":{"class":"diffuse","kd":[0.3,0.3,0.3]})",
                            R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"w"})"));
  ASSERT_TRUE(s);
  const Estimate e = estimate(*s, make_ray(Vec3(0, 0, 4), Vec3(0.2f, -0.1f, -1)), 20000, 3);
  EXPECT_NEAR(e.mean, 0.3, 5.0 * e.se + 1e-4);
  // Bites: a darker object is told apart.
  EXPECT_GT(std::abs(e.mean - 0.35), 5.0 * e.se);
}

// A diffuse floor (kd 0.5) lit by one light kind; mean radiance of one floor point by the three
// strategies.
const char* kDiffuseFloor = R"({"class":"diffuse","kd":0.5})";

void expect_strategies_agree(const std::string& light_json, const std::string& extra_objects,
                             const std::string& settings, const char* what,
                             const std::string& floor = kDiffuseFloor) {
  auto s = parse_ok(R"({"settings":{"integrator":"path")" + settings + R"(},"ambient":{"type":"none"},
      "materials":{"floor":)" + floor + R"(,"lamp":{"class":"diffuse","kd":0,"emission":[4,4,4]}},
      "lights":[)" + light_json + R"(],
      "objects":[{"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":40,"material":"floor"})" +
                    extra_objects + "]}");
  ASSERT_TRUE(s) << what;
  const Ray ray = make_ray(Vec3(0, 3, 3), Vec3(0.1f, -3, -3));
  PathOptions mis, light, bsdf;
  mis.max_bounces = light.max_bounces = bsdf.max_bounces = 1;  // direct light only
  light.strategy = LightStrategy::kLightOnly;
  bsdf.strategy = LightStrategy::kBsdfOnly;
  const Estimate a = estimate(*s, ray, 60000, 21, mis);
  const Estimate b = estimate(*s, ray, 60000, 22, light);
  const Estimate c = estimate(*s, ray, 200000, 23, bsdf);
  EXPECT_GT(a.mean, 0.01) << what;
  EXPECT_NEAR(a.mean, b.mean, 5.0 * std::hypot(a.se, b.se)) << what;
  EXPECT_NEAR(a.mean, c.mean, 5.0 * std::hypot(a.se, c.se)) << what;
  // MIS is never worse than the weaker strategy alone (per path, same count).
  EXPECT_LT(a.se, std::max(b.se, c.se * std::sqrt(200000.0 / 60000.0))) << what;
}

TEST(PathTracer, EachLightKindSampledByLightByBsdfAndByMisHasOneMean) {
  expect_strategies_agree(R"({"type":"spherical","position":[0.5,2,0],"radius":0.8,"color":1})", "", "",
                          "spherical");
  expect_strategies_agree(R"({"type":"directional","direction":[0.3,-1,0.2],"color":1,"angular_radius":20})", "",
                          "", "directional with an angular radius");
  expect_strategies_agree("", R"(,{"type":"plane","point":[0,1.5,0],"normal":[0,-1,0],"size":1.5,"material":"lamp"})",
                          "", "emissive quad");
  expect_strategies_agree("", "", R"(,"background":[0.7,0.7,0.7])", "constant environment");
  // A polished floor: the coat's mirror choice and the (1 - p) in the base's density.
  const std::string polished = R"({"class":"polished","kd":[0.6,0.5,0.4],"r0":0.3,"kh":0})";
  expect_strategies_agree("", R"(,{"type":"plane","point":[0,1.5,0],"normal":[0,-1,0],"size":1.5,"material":"lamp"})",
                          "", "emissive quad over a polished floor", polished);
  expect_strategies_agree(R"({"type":"spherical","position":[0.5,2,0],"radius":0.8,"color":1})", "", "",
                          "spherical light over a polished floor", polished);
}

TEST(PathTracer, GgxMetalsConserveEnergyAndItsStrategiesAgree) {
  // A glTF metal (roughness 0.5: GGX, alpha 0.25) of k_s = 1 in a white furnace: at most 1, and
  // single-scattering GGX loses only a little.
  auto s = parse_ok(furnace(R"("w":{"class":"metal","ks":1})",
                            R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"w"})"));
  ASSERT_TRUE(s);
  s->materials[0].roughness = 0.5f;
  const Estimate e = estimate(*s, make_ray(Vec3(0, 0, 4), Vec3(0.3f, 0.1f, -1)), 20000, 41);
  EXPECT_LE(e.mean, 1.0 + 5 * e.se);
  EXPECT_GT(e.mean, 0.85);
  // A rough metal floor under an emissive quad: light, BSDF and MIS sampling agree.
  auto f = parse_ok(R"({"settings":{"integrator":"path"},"ambient":{"type":"none"},
      "materials":{"floor":{"class":"metal","ks":[0.9,0.7,0.5]},"lamp":{"class":"diffuse","kd":0,"emission":4}},
      "objects":[{"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":40,"material":"floor"},
                 {"type":"plane","point":[0,1.5,-1],"normal":[0,-1,0],"size":2,"material":"lamp"}]})");
  ASSERT_TRUE(f);
  f->materials[0].roughness = 0.6f;
  const Ray ray = make_ray(Vec3(0, 1, 2), Vec3(0, -1, -1.2f));
  PathOptions mis, light, bsdf;
  mis.max_bounces = light.max_bounces = bsdf.max_bounces = 1;
  light.strategy = LightStrategy::kLightOnly;
  bsdf.strategy = LightStrategy::kBsdfOnly;
  const Estimate a = estimate(*f, ray, 60000, 42, mis), b = estimate(*f, ray, 60000, 43, light),
                 c = estimate(*f, ray, 200000, 44, bsdf);
  EXPECT_GT(a.mean, 0.05);
  EXPECT_NEAR(a.mean, b.mean, 5.0 * std::hypot(a.se, b.se));
  EXPECT_NEAR(a.mean, c.mean, 5.0 * std::hypot(a.se, c.se));
}

TEST(PathTracer, GltfNonMetalsConserveEnergyAndTheirStrategiesAgree) {
  // A glTF plastic (white base, 0.04 GGX coat of roughness 0.3) in a white furnace: at most 1.
  auto s = parse_ok(furnace(R"("w":{"class":"polished","kd":1,"r0":0.04,"kh":0})",
                            R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"w"})"));
  ASSERT_TRUE(s);
  s->materials[0].roughness = 0.3f;
  const Estimate e = estimate(*s, make_ray(Vec3(0, 0, 4), Vec3(0.3f, 0.1f, -1)), 20000, 51);
  EXPECT_LE(e.mean, 1.0 + 5 * e.se);
  EXPECT_GT(e.mean, 0.85);
  // A glossy plastic floor (roughness 0.15) under an emissive quad: light, BSDF and MIS agree.
  auto f = parse_ok(R"({"settings":{"integrator":"path"},"ambient":{"type":"none"},
      "materials":{"floor":{"class":"diffuse","kd":[0.6,0.3,0.2]},"lamp":{"class":"diffuse","kd":0,"emission":4}},
      "objects":[{"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":40,"material":"floor"},
                 {"type":"plane","point":[0,1.5,-1],"normal":[0,-1,0],"size":2,"material":"lamp"}]})");
  ASSERT_TRUE(f);
  f->materials[0].roughness = 0.15f;
  f->materials[0].r0 = Vec3(0.04f);
  const Ray ray = make_ray(Vec3(0, 1, 2), Vec3(0, -1, -1.2f));
  PathOptions mis, light, bsdf;
  mis.max_bounces = light.max_bounces = bsdf.max_bounces = 1;
  light.strategy = LightStrategy::kLightOnly;
  bsdf.strategy = LightStrategy::kBsdfOnly;
  const Estimate a = estimate(*f, ray, 60000, 52, mis), b = estimate(*f, ray, 60000, 53, light),
                 c = estimate(*f, ray, 200000, 54, bsdf);
  EXPECT_GT(a.mean, 0.05);
  EXPECT_NEAR(a.mean, b.mean, 5.0 * std::hypot(a.se, b.se));
  EXPECT_NEAR(a.mean, c.mean, 5.0 * std::hypot(a.se, c.se));
}

TEST(PathTracer, PolishedWithAColouredCoatNeverReflectsMoreThanComesIn) {
  // White base under a strongly coloured coat in a white furnace: each channel at most 1.
  auto s = parse_ok(furnace(R"("w":{"class":"polished","kd":1,"r0":[0.9,0.1,0.1],"kh":0})",
                            R"({"type":"sphere","center":[0,0,0],"radius":1,"material":"w"})"));
  ASSERT_TRUE(s);
  for (const Vec3& dir : {Vec3(0, 0, -1), Vec3(0.6f, 0.1f, -1)}) {
    const Ray ray = make_ray(Vec3(0, 0, 4), dir);
    for (int k = 0; k < 3; ++k) {
      double sum = 0, sum2 = 0;
      const int n = 20000;
      for (int i = 0; i < n; ++i) {
        const double v = trace_path(*s, ray, mix64(uint64_t(31 + k) << 32 | uint64_t(i)))[k];
        sum += v;
        sum2 += v * v;
      }
      const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
      EXPECT_LE(mean, 1.0 + 5 * se + 1e-4) << "channel " << k;
      EXPECT_GT(mean, 0.5) << "channel " << k;
    }
  }
}

TEST(PathTracer, OneBounceFromAPointLightIsWhittedsDiffuseTerm) {
  for (const char* light : {R"({"type":"point","position":[1,4,2],"color":[0.9,0.6,0.3]})",
                            R"({"type":"directional","direction":[-0.2,-1,0.4],"color":[0.5,0.7,0.9]})"}) {
    auto s = parse_ok(R"({"settings":{"integrator":"path"},"ambient":{"type":"none"},
        "materials":{"floor":{"class":"diffuse","kd":[0.8,0.5,0.2]}},"lights":[)" + std::string(light) + R"(],
        "objects":[{"type":"plane","point":[0,0,0],"normal":[0,1,0],"size":40,"material":"floor"}]})");
    ASSERT_TRUE(s);
    PathOptions direct;
    direct.max_bounces = 1;
    for (const Vec3& dir : {Vec3(0, -1, -1), Vec3(0.4f, -1, -0.3f)}) {
      const Ray ray = make_ray(Vec3(0, 3, 3), dir);
      const Vec3 path = trace_path(*s, ray, 5, nullptr, nullptr, nullptr, nullptr, nullptr, direct);
      const Vec3 whitted = trace_radiance(*s, ray, 0, Vec3(1.0f), nullptr);
      ASSERT_GT(whitted.x, 0.05f);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(path[k], whitted[k], 1e-5f * whitted[k] + 1e-7f) << light;
    }
  }
}

TEST(PathTracer, DeterministicAndPacketsGiveTheSameSamples) {
  auto s = load_scene("cornell");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const Scene& scene = **s;
  EXPECT_EQ(scene.settings.integrator, Integrator::kPath);
  const CameraBasis cam = make_camera_basis(scene.camera, 64, 64);
  float px[64], py[64];
  for (int i = 0; i < 64; ++i) {
    px[i] = 20.0f + float(i % 8) + 0.37f;
    py[i] = 30.0f + float(i / 8) + 0.61f;
  }
  Hit hits[64];
  primary_hits(scene, cam, 64, px, py, hits);
  for (int i = 0; i < 64; ++i) {
    const SampleResult a = trace_sample(scene, cam, px[i], py[i], 1234 + i);
    const SampleResult b = trace_sample(scene, cam, px[i], py[i], 1234 + i);
    const SampleResult c = trace_sample(scene, cam, px[i], py[i], 1234 + i, nullptr, &hits[i]);
    ASSERT_TRUE(a.valid);
    EXPECT_EQ(a.color, b.color);
    EXPECT_EQ(a.color, c.color);
    EXPECT_EQ(a.depth, c.depth);
  }
  // Fresh numbers per update: two seeds differ somewhere.
  int differ = 0;
  for (int i = 0; i < 64; ++i)
    differ += trace_sample(scene, cam, px[i], py[i], 1).color != trace_sample(scene, cam, px[i], py[i], 2).color;
  EXPECT_GT(differ, 32);
}

TEST(PathTracer, IntegratorDefaultsToPathOnlyWhereSomethingEmits) {
  auto cornell = load_scene("cornell");
  auto plain = load_scene("default");
  ASSERT_TRUE(cornell.ok() && plain.ok());
  EXPECT_EQ((*cornell)->settings.integrator, Integrator::kPath);
  EXPECT_FALSE((*cornell)->emitters.empty());
  EXPECT_EQ((*plain)->settings.integrator, Integrator::kWhitted);
  EXPECT_TRUE((*plain)->emitters.empty());  // no emitter table, no emitter sampling work
  // The scene may name its own.
  auto named = parse_ok(R"({"settings":{"integrator":"whitted"},
      "materials":{"e":{"class":"diffuse","emission":1}},
      "objects":[{"type":"sphere","center":[0,0,0],"radius":1,"material":"e"}]})");
  ASSERT_TRUE(named);
  EXPECT_EQ(named->settings.integrator, Integrator::kWhitted);
  auto bad = parse_scene_json(R"({"settings":{"integrator":"radiosity"}})", "t.json", ".");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("settings.integrator"), std::string::npos) << bad.error().message;
  for (const char* igi : {R"({"paths":0})", R"({"interleave":9})", R"({"clamp":-0.1})", R"({"vpls":3})"}) {
    auto b = parse_scene_json(std::string(R"({"settings":{"integrator":"igi","igi":)") + igi + "}}", "t.json", ".");
    ASSERT_FALSE(b.ok()) << igi;
    EXPECT_NE(b.error().message.find("settings.igi."), std::string::npos) << b.error().message;
  }
}

TEST(PathTracer, CornellBoxConvergesToAFiniteLitImage) {
  auto s = load_scene("cornell");
  ASSERT_TRUE(s.ok());
  const Scene& scene = **s;
  // The light seen directly is its emission (plus what its white diffuser reflects); the red
  // wall is lit (there is no ambient) and red.
  const CameraBasis cam = make_camera_basis(scene.camera, 64, 64);
  double light = 0.0;
  for (int i = 0; i < 200; ++i) light += trace_sample(scene, cam, 32.0f, 9.0f, 9 + i).color.x / 200;
  EXPECT_GE(light, 17.0);
  EXPECT_LT(light, 17.5);
  Vec3 wall(0.0f);
  for (int i = 0; i < 4000; ++i) {
    const SampleResult r = trace_sample(scene, cam, 3.0f, 32.0f, 100 + i);
    ASSERT_TRUE(r.valid);
    wall += r.color;
  }
  wall /= 4000.0f;
  EXPECT_GT(wall.x, 0.05f);
  EXPECT_GT(wall.x, 4.0f * wall.y);
}

}  // namespace
}  // namespace frameless
