// The reflection depth view (issue 12): the false-colour ramp, the engine's per-pixel levels in
// the display image (both modes, across a layout change), the GL view drawing exactly the ramp,
// and `capture --view levels` writing PNG frames that the manifest lists, with no stray file
// when a write fails.
#include "display/levels_view.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <set>

#include "../engine/test_shaders.h"
#include "core/scene/texture.h"
#include "core/scenes/scene_load.h"
#include "display/capture.h"
#include "display/display_thread.h"
#include "display/exr_io.h"
#include "display/gl_presenter.h"
#include "display/manifest.h"
#include "display/osmesa_context.h"
#include "display/png_io.h"

namespace fs = std::filesystem;

namespace frameless {
namespace {

using namespace frameless::testing;

const Vec3 kRed(1.0f, 0.0f, 0.0f);

// What levels_shader reports for pixel (x, y): 0..39, so a third of the values saturate.
uint8_t expected_levels(int x, int y) { return uint8_t((7 * x + 3 * y) % 40); }

SampleResult levels_shader(const void* c, const CameraBasis& b, float px, float py, uint64_t seed) {
  SampleResult r = noisy_shader(c, b, px, py, seed);
  r.levels = expected_levels(int(px), int(py));
  return r;
}

TEST(LevelsView, RampRunsFromDarkBlueToRedAt25) {
  const Vec3 zero = levels_color(0);
  EXPECT_GT(zero.z, zero.x);
  EXPECT_GT(zero.z, zero.y);
  EXPECT_LT(zero.z, 0.2f) << "0 levels is dark";
  for (uint32_t l : {25u, 26u, 100u, 255u}) EXPECT_EQ(levels_color(l), kRed) << l;
  float red = -1.0f;
  for (uint32_t a = 0; a < 25; ++a) {
    EXPECT_NE(levels_color(a), kRed) << a;
    for (uint32_t b = a + 1; b < 25; ++b) EXPECT_NE(levels_color(a), levels_color(b)) << a << " " << b;
    EXPECT_GE(levels_color(a).x, red) << "deeper is never less red: " << a;
    red = levels_color(a).x;
  }
  ViewMode m = ViewMode::shaded;
  ASSERT_TRUE(parse_view("levels", m));
  EXPECT_EQ(m, ViewMode::levels);
  EXPECT_STREQ(to_string(ViewMode::levels), "levels");
  EXPECT_FALSE(parse_view("depth", m));
}

void expect_levels(const DisplayImage& img, const char* what) {
  ASSERT_EQ(img.levels.size(), img.pixels()) << what;
  int wrong = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      wrong += img.levels[size_t(y) * size_t(img.width) + size_t(x)] != expected_levels(x, y);
  EXPECT_EQ(wrong, 0) << what;
}

TEST(LevelsView, DisplayImageCarriesTheEngineLevels) {
  for (RenderMode mode : {RenderMode::frameless, RenderMode::conventional}) {
    EngineConfig c = test_config(48, 36, 3, levels_shader);
    c.deterministic = true;
    c.mode = mode;
    c.samples_per_tick = 48 * 36 * 2 * 2;  // every pixel twice per tick
    Engine e(kEmptyScene, c, camera_at(0));
    DisplayThread d(e, {});
    for (int k = 0; k < 3; ++k) d.step();
    expect_levels(d.acquire_latest(), to_string(mode));
    std::vector<uint8_t> engine_levels;
    e.copy_levels(engine_levels);
    EXPECT_TRUE(engine_levels == d.acquire_latest().levels) << to_string(mode);
    // A new partition moves every pixel to a new slot: its levels move with it.
    e.set_threads(5);
    d.tick();
    expect_levels(d.acquire_latest(), "after a layout change");
    d.step();
    expect_levels(d.acquire_latest(), "rendered after a layout change");
  }
}

struct Gl {
  std::unique_ptr<OsMesaContext> ctx;
  std::unique_ptr<GlPresenter> presenter;
};

Gl make_gl(int w, int h) {
  Gl g;
  auto ctx = OsMesaContext::create(w, h);
  EXPECT_TRUE(ctx.ok()) << (ctx.ok() ? "" : ctx.error().message);
  if (!ctx.ok()) return g;
  g.ctx = std::move(ctx.value());
  auto p = GlPresenter::create(&OsMesaContext::proc_address);
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().message);
  if (p.ok()) g.presenter = std::move(p.value());
  return g;
}

TEST(LevelsView, GlViewDrawsTheRampPixelForPixel) {
  Gl g = make_gl(30, 8);
  ASSERT_TRUE(g.presenter);
  DisplayImage img;
  img.reset(30, 8);
  for (size_t i = 0; i < img.pixels(); ++i) {
    img.levels[i] = uint8_t((i * 11) % 31);  // 0..30, scattered
    img.rgb[3 * i] = 0.5f;
  }
  img.levels[17] = 255;
  const ViewScale s = g.presenter->upload(img, ViewMode::levels);
  EXPECT_EQ(s.max_levels, 255);
  std::vector<float> back;
  ASSERT_TRUE(g.presenter->render_linear(back).ok());
  ASSERT_EQ(back.size(), 3 * img.pixels());
  int wrong = 0;
  for (size_t i = 0; i < img.pixels(); ++i)
    wrong += Vec3(back[3 * i], back[3 * i + 1], back[3 * i + 2]) != levels_color(img.levels[i]);
  EXPECT_EQ(wrong, 0);
  // The shaded view of the same image is untouched by the levels.
  g.presenter->upload(img, ViewMode::shaded);
  ASSERT_TRUE(g.presenter->render_linear(back).ok());
  EXPECT_TRUE(back == img.rgb);
}

fs::path test_root() {
  return fs::temp_directory_path() / ("frameless_levels_test_" + std::to_string(getpid()));
}

struct ScratchCleanup : ::testing::Environment {
  void TearDown() override { fs::remove_all(test_root()); }
};
[[maybe_unused]] ::testing::Environment* const cleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

std::string temp_dir(const std::string& name) {
  const fs::path p = test_root() / name;
  fs::remove_all(p);
  return p.string();
}

std::set<std::string> files_in(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

const Scene& scene() {
  static std::unique_ptr<Scene> s = [] {
    auto r = load_scene("default");  // metal and glass spheres: levels > 0 somewhere
    EXPECT_TRUE(r.ok());
    return std::move(r.value());
  }();
  return *s;
}

CaptureOptions levels_options(const std::string& out) {
  CaptureOptions o;
  o.out_dir = out;
  o.duration = 0.5;
  o.refresh_hz = 10.0;
  o.engine.width = 40;
  o.engine.height = 30;
  o.engine.threads = 2;
  o.engine.chunk_size = 16;
  o.engine.deterministic = true;
  o.engine.samples_per_tick = 40 * 30 * 2;
  o.camera = scene().camera;
  o.layers = {"levels"};
  o.views = {"levels"};
  o.contact_sheet = false;
  o.mp4 = false;
  return o;
}

// Each frame's PNG is the ramp of the levels its EXR carries (sRGB-encoded, as the viewer shows it).
TEST(LevelsView, CaptureWritesLevelsFramesTheManifestLists) {
  const std::string dir = temp_dir("capture");
  auto r = run_capture(scene(), levels_options(dir));
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->frames, 5);
  auto m = read_manifest(dir + "/manifest.json");
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->settings["views"], nlohmann::json::array({"levels"}));
  std::set<std::string> expected = {"manifest.json"};
  int deep = 0;
  for (const ManifestFrame& f : m->frames) {
    ASSERT_EQ(f.views.size(), 1u);
    EXPECT_EQ(f.views.at("levels"), capture_view_name("levels", f.index));
    expected.insert({f.file, f.views.at("levels")});
    auto exr = read_exr(dir + "/" + f.file);
    ASSERT_TRUE(exr.ok()) << exr.error().message;
    auto png = load_image(dir + "/" + f.views.at("levels"));
    ASSERT_TRUE(png.ok()) << png.error().message;
    const Image& im = *png.value();
    ASSERT_EQ(im.width, 40);
    ASSERT_EQ(im.height, 30);
    ASSERT_EQ(im.channels, 3);
    const std::vector<float>& levels = exr->channels["levels"];
    ASSERT_EQ(levels.size(), 40u * 30u);
    int wrong = 0;
    for (size_t i = 0; i < levels.size(); ++i) {
      const Vec3 c = levels_color(uint32_t(levels[i]));
      for (int k = 0; k < 3; ++k) wrong += im.ldr[3 * i + size_t(k)] != linear_to_srgb8(c[k]);
      deep += levels[i] > 0.0f;
    }
    EXPECT_EQ(wrong, 0) << f.file;
  }
  EXPECT_EQ(files_in(dir), expected);
  EXPECT_GT(deep, 0) << "the default scene's metal and glass show levels";
}

TEST(LevelsView, FailedWriteLeavesNoStrayLevelsFrame) {
  for (const char* failing : {"levels_00003.png", "frame_00003.exr", "manifest.json"}) {
    const std::string dir = temp_dir(std::string("fail_") + failing);
    int manifest_writes = 0;
    CaptureHooks hooks;
    hooks.before_write = [&](const std::string& path) -> std::optional<std::string> {
      const std::string name = fs::path(path).filename().string();
      // The manifest's 5th write lists frame 3 (writes: initial, 0, 1, 2, 3).
      if (name == "manifest.json" && ++manifest_writes == 5 && std::string(failing) == name)
        return "No space left on device (injected)";
      if (name == failing && name != "manifest.json") return "No space left on device (injected)";
      return std::nullopt;
    };
    auto r = run_capture(scene(), levels_options(dir), hooks);
    ASSERT_FALSE(r.ok()) << failing;
    EXPECT_NE(r.error().message.find("3 frames written"), std::string::npos) << r.error().message;
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"frame_00000.exr", "frame_00001.exr",
                                                     "frame_00002.exr", "levels_00000.png",
                                                     "levels_00001.png", "levels_00002.png",
                                                     "manifest.json"}))
        << failing;
  }
}

TEST(LevelsView, BadViewsAreRejected) {
  for (std::vector<std::string> views :
       {std::vector<std::string>{"shaded"}, {"depth"}, {"levels", "levels"}}) {
    CaptureOptions o = levels_options(temp_dir("bad"));
    o.views = views;
    auto r = run_capture(scene(), o);
    ASSERT_FALSE(r.ok()) << views[0];
    EXPECT_NE(r.error().message.find("--view"), std::string::npos) << r.error().message;
  }
  // The viewer's one-line refusal: tests/cli/capture_view_cli_test.cpp.
}

}  // namespace
}  // namespace frameless
