// The public C++ API (include/frameless/api.h): scenes load from names, files and JSON text;
// render() gives what the library renders; an engine runs, follows the camera, lights and
// materials, shows its image and per-pixel state; every bad input is an error result with the
// command line's one-line message, never an exit.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>

#include "frameless/api.h"

namespace frameless::api {
namespace {

double mean(const Image& img, int c = 0) {
  double s = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) s += img.at(x, y, c);
  return s / double(img.width * img.height);
}

constexpr const char* kBall = R"({"camera": {"eye": [0, 0, 4], "look": [0, 0, 0]},
  "lights": [{"type": "point", "position": [2, 3, 4], "color": 1}],
  "ambient": {"type": "none"},
  "materials": {"ball": {"class": "diffuse", "kd": [0.8, 0.2, 0.1]}},
  "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "ball"}]})";

TEST(Api, ScenesLoadFromNamesFilesAndJsonAndRender) {
  auto s = Scene::load("default");
  ASSERT_TRUE(s) << s.error();
  EXPECT_EQ(s->info().name, "default");
  EXPECT_GT(s->info().materials.size(), 3u);
  RenderOptions o;
  o.width = 48;
  o.height = 32;
  o.spp = 2;
  auto img = render(*s, o);
  ASSERT_TRUE(img) << img.error();
  EXPECT_EQ(img->width, 48);
  EXPECT_EQ(img->channels, 3);
  ASSERT_EQ(img->data.size(), size_t(48 * 32 * 3));
  for (float v : img->data) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GT(mean(*img), 0.01);
  // JSON text: the red ball, red in the middle and black around it.
  auto ball = Scene::from_json(kBall);
  ASSERT_TRUE(ball) << ball.error();
  auto b = render(*ball, o);
  ASSERT_TRUE(b);
  EXPECT_GT(b->at(24, 16, 0), 3.0f * b->at(24, 16, 2));
  EXPECT_EQ(b->at(0, 0, 0), 0.0f);
  // A camera looking away sees nothing.
  Camera away = ball->camera();
  away.look = {0, 0, 8};
  o.camera = away;
  EXPECT_EQ(mean(*render(*ball, o)), 0.0);
}

TEST(Api, BadInputIsAnErrorResultWithTheCommandLinesMessage) {
  auto missing = Scene::load("/nonexistent/scene.json");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("/nonexistent/scene.json"), std::string::npos);
  EXPECT_EQ(missing.error().find('\n'), std::string::npos);
  auto typo = Scene::from_json(R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": -1, "material": "x"}]})");
  ASSERT_FALSE(typo);
  EXPECT_NE(typo.error().find("objects[0]"), std::string::npos) << typo.error();
  auto s = Scene::from_json(kBall);
  ASSERT_TRUE(s);
  RenderOptions o;
  o.width = -3;
  EXPECT_FALSE(render(*s, o));
  o = {};
  o.camera = Camera{{0, 0, 1}, {0, 0, 1}, {0, 1, 0}, 45};
  EXPECT_NE(render(*s, o).error().find("camera"), std::string::npos);
  EngineOptions e;
  e.mode = "sideways";
  EXPECT_NE(Engine::start(*s, e).error().find("mode"), std::string::npos);
  e = {};
  e.alpha = 0;
  EXPECT_FALSE(Engine::start(*s, e));
}

// The command line's output for `args` (stdout and stderr).
std::string cli_output(const std::string& args) {
  std::string out;
  if (FILE* p = popen((std::string(FRAMELESS_BINARY) + " " + args + " 2>&1").c_str(), "r")) {
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    pclose(p);
  }
  return out;
}

TEST(Api, ErrorsAreTheCommandLinesOwnLines) {
  const std::string dir = ::testing::TempDir();
  const std::string bad = dir + "api_bad.json";
  std::FILE* f = std::fopen(bad.c_str(), "w");
  ASSERT_TRUE(f);
  std::fputs(R"({"objects": [{"type": "sphere", "center": [0, 0, 0], "radius": -1, "material": "x"}]})", f);
  std::fclose(f);
  for (const std::string& spec : {bad, std::string("/nonexistent/scene.json"), std::string("spheres:0")}) {
    auto s = Scene::load(spec);
    ASSERT_FALSE(s) << spec;
    EXPECT_EQ(cli_output("render " + spec + " --out " + dir + "api_never.exr"), "frameless: " + s.error() + "\n") << spec;
  }
}

TEST(Api, AnEngineFollowsCameraLightsAndMaterials) {
  auto s = Scene::from_json(kBall);
  ASSERT_TRUE(s);
  EngineOptions o;
  o.width = 32;
  o.height = 32;
  o.threads = 2;
  o.deterministic = true;
  o.samples_per_tick = 32 * 32 * 4;
  auto e = Engine::start(*s, o);
  ASSERT_TRUE(e) << e.error();
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(e->advance());
  const Image first = e->image();
  EXPECT_GT(first.at(16, 16, 0), 0.1f);
  auto count = e->state("count");
  ASSERT_TRUE(count);
  EXPECT_GT(count->at(16, 16), 0.0f);
  EXPECT_FALSE(e->state("colour"));
  // Blue ball: the material's colour reaches the image.
  ASSERT_TRUE(e->set_material_color("ball", {0.1f, 0.2f, 0.8f}));
  for (int k = 0; k < 8; ++k) ASSERT_TRUE(e->advance());
  const Image blue = e->image();
  EXPECT_GT(blue.at(16, 16, 2), blue.at(16, 16, 0));
  // The light moved behind the ball: its front goes dark.
  ASSERT_TRUE(e->set_light(0, Light{{0, 0, -6}, {1, 1, 1}, 0.0f, false}));
  for (int k = 0; k < 8; ++k) ASSERT_TRUE(e->advance());
  EXPECT_LT(e->image().at(16, 16, 2), 0.2f * blue.at(16, 16, 2));
  EXPECT_FALSE(e->set_light(3, Light{}));
  const Result<bool> negative = e->set_light(0, Light{{0, 0, -6}, {-1, 1, 1}, 0.0f, false});
  ASSERT_FALSE(negative);
  EXPECT_NE(negative.error().find("colour must be finite and >= 0"), std::string::npos) << negative.error();
  EXPECT_FALSE(e->set_material_color("nope", {1, 1, 1}));
  // The camera turned away: the ball leaves the middle.
  ASSERT_TRUE(e->set_camera(Camera{{0, 0, 4}, {3, 0, 0}, {0, 1, 0}, 30}));
  for (int k = 0; k < 8; ++k) ASSERT_TRUE(e->advance());
  EXPECT_EQ(e->image().at(16, 16, 2), 0.0f);
  const EngineStats st = e->stats();
  EXPECT_GT(st.samples, uint64_t(20000));
  EXPECT_GT(st.pixel_updates, 0u);
  e->stop();
  EXPECT_FALSE(e->running());
  EXPECT_FALSE(e->advance());
}

TEST(Api, MovingObjectsAndInstancesMoveWhereTheyAreTold) {
  // A moving sphere and an instanced triangle pair, both starting in the middle of the view.
  auto s = Scene::from_json(R"({"camera": {"eye": [0, 0, 4], "look": [0, 0, 0]}, "ambient": {"type": "constant", "color": 1},
    "materials": {"m": {"class": "diffuse", "kd": [0.9, 0.1, 0.1]}, "q": {"class": "diffuse", "kd": [0.1, 0.1, 0.9]}},
    "meshes": {"quad": {"type": "triangles", "vertices": [[-0.3,-0.3,0],[0.3,-0.3,0],[0.3,0.3,0],[-0.3,0.3,0]],
                        "indices": [[0,1,2],[0,2,3]], "material": "q"}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.3, "material": "m", "dynamic": true},
                {"type": "instance", "mesh": "quad", "transform": {"translate": [0, 0, -1]}}]})");
  ASSERT_TRUE(s) << s.error();
  EXPECT_EQ(s->info().moving_objects, 1u);
  EngineOptions o;
  o.width = o.height = 32;
  o.threads = 1;
  o.deterministic = true;
  o.samples_per_tick = 32 * 32 * 2;
  auto e = Engine::start(*s, o);
  ASSERT_TRUE(e) << e.error();
  const auto settle = [&] { for (int k = 0; k < 6; ++k) ASSERT_TRUE(e->advance()); };
  settle();
  EXPECT_GT(e->image().at(16, 16, 0), 0.5f);  // the red sphere in front
  ASSERT_TRUE(e->set_object_position(0, {5, 0, 0}));
  settle();
  EXPECT_GT(e->image().at(16, 16, 2), 0.5f);  // gone: the blue instance behind shows
  ASSERT_TRUE(e->set_instance_transform(0, {1, 0, 0, 9, 0, 1, 0, 0, 0, 0, 1, -1}));
  settle();
  EXPECT_EQ(e->image().at(16, 16, 2), 0.0f);  // and it moved away too
  EXPECT_FALSE(e->set_object_position(1, {0, 0, 0}));
  EXPECT_FALSE(e->set_instance_transform(0, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}));  // singular
  EXPECT_FALSE(e->set_instance_transform(4, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}));
}

TEST(Api, AWallClockEngineRendersOnItsOwnThreads) {
  auto s = Scene::load("default");
  ASSERT_TRUE(s);
  EngineOptions o;
  o.width = 64;
  o.height = 48;
  o.threads = 2;
  auto e = Engine::start(*s, o);
  ASSERT_TRUE(e) << e.error();
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  const EngineStats st = e->stats();
  EXPECT_GT(st.samples, 0u);
  EXPECT_GT(st.display_ticks, 0u);
  EXPECT_GT(mean(e->image()), 0.0);
  e->stop();
  e->stop();  // idempotent
}

TEST(Api, CapturesAndTheUpdateDistribution) {
  auto s = Scene::load("default");
  ASSERT_TRUE(s);
  const std::string dir = ::testing::TempDir() + "api_capture";
  CaptureOptions c;
  c.out_dir = dir;
  c.duration = 0.3;
  c.refresh_hz = 10;
  c.width = 48;
  c.height = 32;
  c.deterministic = true;
  c.orbit_degrees = 20;
  c.layers = {"age", "count"};
  auto info = capture(*s, c);
  ASSERT_TRUE(info) << info.error();
  EXPECT_EQ(info->frames, 3);
  EXPECT_EQ(info->manifest, dir + "/manifest.json");
  c.out_dir = "/proc/no-such-place";
  auto bad = capture(*s, c);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().find('\n'), std::string::npos);
  c.out_dir = dir;
  c.layers = {"colour"};
  EXPECT_FALSE(capture(*s, c));
  // Deterministic frameless order: every pixel updated once per sweep, the camera change seen by
  // every pixel within 1 + update % / 100 sweeps.
  UpdateStatisticsOptions o;
  o.threads = 2;
  auto st = update_statistics(*s, o);
  ASSERT_TRUE(st) << st.error();
  EXPECT_EQ(st->updates_min, st->updates_max);
  EXPECT_NEAR(st->updates_mean, 4.0, 1e-9);
  EXPECT_TRUE(st->staleness_measured);
  EXPECT_LE(st->t100_sweeps, st->bound_sweeps + 1e-9);
  EXPECT_EQ(st->thread_pixels.size(), 2u);
  EXPECT_TRUE(st->balanced);
  o.width = 0;
  EXPECT_FALSE(update_statistics(*s, o));
}

}  // namespace
}  // namespace frameless::api
