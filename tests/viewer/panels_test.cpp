// The panels under Xvfb: a screenshot shows them over the image; scripted input opens a panel and
// changes a value through the panel's control, and the image follows; scene-level settings and
// opening files restart the session cleanly; bad values are one line each and change nothing.
#include <gtest/gtest.h>

#include <regex>

#include "core/scenes/scene_load.h"
#include "display/camera_path.h"
#include "viewer/viewer.h"
#include "viewer_test_util.h"

namespace frameless {
namespace {

fs::path folder(const char* name) {
  const fs::path p = scratch() / name;
  fs::create_directories(p);
  return p;
}

ExrImage screenshot(const fs::path& p, const std::string& log) {
  auto r = read_exr(p.string());
  EXPECT_TRUE(r.ok()) << log;
  return r.ok() ? r.value() : ExrImage{};
}

// 480x300 window: the panels take the left 240 columns; the image's right part is x >= 280.
constexpr int kPanelRight = 220, kImageLeft = 280, kWidth = 480;

TEST(Panels, ShowOverTheImageAndALightControlTintsIt) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("tint");
  const fs::path plain = dir / "plain.exr", shown = dir / "shown.exr", blue = dir / "blue.exr",
                 hidden = dir / "hidden.exr";
  std::string log;
  const int status = run_viewer_script(
      "default --size 480x300 --threads 2",
      // Late enough that every pixel has samples even under the sanitizers beside a parallel
      // ctest (at 2.5 s the blue mean beside the panel still rose 3.1 % by 3.3 s there once).
      "0.1 key O\n5.5 screenshot " + plain.string() + "\n5.6 panel lights\n6.3 screenshot " +
          shown.string() + "\n6.4 set light0.color 0.05 0.05 1\n" +
          "8.8 screenshot " + blue.string() + "\n8.9 key TAB\n9.4 screenshot " + hidden.string() + "\n9.5 quit\n",
      dir, &log);
  ASSERT_EQ(status, 0) << log;
  const ExrImage a = screenshot(plain, log), b = screenshot(shown, log), c = screenshot(blue, log),
                 d = screenshot(hidden, log);
  ASSERT_EQ(a.width, kWidth) << log;
  // The panels cover the left of the window and leave the rest of the image as it was: there
  // pixels only lose noise between the two screenshots (per pixel 0.025-0.056 under ASan beside a
  // parallel ctest, 5e-5 alone), far less than where the panel is drawn (0.46), and its
  // brightness stays (a mean over the region, which the noise does not move).
  const double panel = mean_difference(a, b, 0, kPanelRight), rest = mean_difference(a, b, kImageLeft, kWidth);
  EXPECT_GT(panel, 0.05);
  EXPECT_GT(panel, 3.0 * rest) << "panel " << panel << ", rest of the image " << rest;
  for (const char* c : {"R", "G", "B"})
    EXPECT_NEAR(channel_mean(b, c, kImageLeft, kWidth), channel_mean(a, c, kImageLeft, kWidth),
                0.03 * channel_mean(a, c, kImageLeft, kWidth)) << c;
  // A blue light: the image's blue-to-red ratio rises (1.04 before; 1.54 after 1.6 s under ASan
  // beside a parallel ctest on one machine, only 1.26 on a slower one (an AMD EPYC Zen 3), more
  // when the machine is free; 1.035, a rise of none, when the control does nothing). So 2.4 s, and
  // a rise of 15 %. The script's times are those of the slower machine under ASan.
  auto ratio = [](const ExrImage& e) { return channel_mean(e, "B", kImageLeft, kWidth) / channel_mean(e, "R", kImageLeft, kWidth); };
  EXPECT_GT(ratio(c), 1.15 * ratio(b)) << ratio(b) << " -> " << ratio(c);
  // Tab hides the panels: the left shows the (blue) image again, not the panel.
  EXPECT_GT(mean_difference(c, d, 0, kPanelRight), 0.05);
  EXPECT_GT(channel_mean(d, "B", 0, kPanelRight), channel_mean(d, "R", 0, kPanelRight));
  EXPECT_NE(log.find("with panels"), std::string::npos) << log;
}

TEST(Panels, BadControlValuesAreOneLineEachAndTheViewerGoesOn) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("bad");
  std::string log;
  const int status = run_viewer_script(
      "default --size 160x100 --threads 1",
      "0.5 set light9.color 1 0 0\n0.6 set alpha 2\n0.7 set integrator fast\n"
      "0.8 set camera.load /nonexistent/path.json\n0.9 set volume0.isovalue 1\n"
      "1.0 set material0.kd 1 x 0\n1.1 set camera.fov 0\n1.2 set nothing.here 1\n"
      "1.3 open /nonexistent/model.obj\n1.4 set light0.color -1 0 0\n1.6 quit\n",
      dir, &log);
  ASSERT_EQ(status, 0) << log;  // none of them stops the viewer
  const std::string s = (dir / "script.txt").string();
  for (const std::string& line :
       {s + ":1: light9.color: the scene has 1 light", s + ":2: alpha: must be in (0, 1]",
        s + ":3: integrator: expected whitted, path or igi", s + ":4: /nonexistent/path.json: cannot open",
        s + ":5: volume0.isovalue: the scene has 0 volumes", s + ":6: material0.kd: 'x' is not a number",
        s + ":7: camera.fov: the camera would be degenerate", s + ":8: nothing.here: unknown control",
        std::string("frameless: /nonexistent/model.obj"),
        s + ":10: light0.color: light 0: colour must be finite and >= 0"})
    EXPECT_NE(log.find(line), std::string::npos) << line << "\n" << log;
}

// Where ImGui is not wanted (or cannot run) the viewer keeps its keys and overlay: a script that
// opens a panel says so in one line, and the controls still work.
TEST(Panels, WithoutPanelsTheOverlayAndControlsRemain) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("none");
  const fs::path plain = dir / "plain.exr", red = dir / "red.exr";
  std::string log;
  const int status = run_viewer_script(
      "default --size 160x100 --threads 2 --no-panels",
      "0.3 panel lights\n0.4 key TAB\n1.5 screenshot " + plain.string() + "\n1.6 set light0.color 1 0.05 0.05\n" +
          "3.2 screenshot " + red.string() + "\n3.3 quit\n",
      dir, &log);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("script.txt:1: panel: the panels are not available here"), std::string::npos) << log;
  EXPECT_NE(log.find("(0 with panels)"), std::string::npos) << log;  // none drawn, Tab or not
  const ExrImage a = screenshot(plain, log), b = screenshot(red, log);
  EXPECT_GT(channel_mean(b, "R", 0, b.width) / channel_mean(b, "B", 0, b.width),
            1.3 * channel_mean(a, "R", 0, a.width) / channel_mean(a, "B", 0, a.width));
}

TEST(Panels, ScriptsNamingPanelsAndControlsAreChecked) {
  auto ok = parse_viewer_script("0 panel volumes\n1 set light0.color 1 0 0\n2 open x.obj\n", "s.txt");
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ((*ok)[1].args.size(), 4u);
  for (const char* bad : {"1 panel nope", "1 set alpha", "1 set", "1 open", "1 panel", "1 resize abc 10",
                          "1 resize 1e10 100", "1 orbit 3 nan", "1 zoom 2x", "1 fly 1 0 0 inf"}) {
    auto r = parse_viewer_script(std::string("0 quit\n") + bad + "\n", "s.txt");
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().message.rfind("s.txt:2: ", 0), 0u) << r.error().message;
  }
}

// Integrator, shadows, acceleration structure, closed loop: each restarts the session (new
// engine, same camera and display settings); then a file opened from the window replaces the scene.
TEST(Panels, SceneSettingsAndOpeningAFileRestartTheSession) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("session");
  const fs::path whitted = dir / "whitted.exr", path = dir / "path.exr", opened = dir / "opened.exr",
                 camera_before = dir / "before.json", camera_after = dir / "after.json";
  const std::string mesh = std::string(FRAMELESS_TEST_DATA) + "/meshes/tetra.obj";
  std::string log;
  const int status = run_viewer_script(
      "default --size 200x120 --threads 2",
      "0.1 key O\n2.4 screenshot " + whitted.string() + "\n2.45 set camera.save " + camera_before.string() +
          "\n2.5 set integrator igi\n2.7 set accel grid\n" +
          "2.8 set closed_loop on\n2.9 set mode conventional\n3.1 set mode frameless\n3.2 set shadows hard\n" +
          "3.3 set integrator path\n5.4 screenshot " + path.string() + "\n5.45 set camera.save " +
          camera_after.string() + "\n5.5 open " + mesh +
          "\n7.2 screenshot " + opened.string() + "\n7.3 quit\n",
      dir, &log);
  ASSERT_EQ(status, 0) << log;
  for (const char* line : {"integrator igi (render threads restarted)", "acceleration grid (render threads restarted)",
                           "closed loop on (render threads restarted)", "shadows hard (render threads restarted)",
                           "integrator path (render threads restarted)"})
    EXPECT_NE(log.find(line), std::string::npos) << line << "\n" << log;
  const ExrImage a = screenshot(whitted, log), b = screenshot(path, log), c = screenshot(opened, log);
  EXPECT_GT(distinct_colours(b), 100u) << log;  // the restarted engine renders the scene
  // The same view: the camera saved before and after the restarts is the same file, and the
  // images' structure agrees (the correlation of 10-pixel block averages: 0.93 here, -0.30 against
  // the opened scene). Per-pixel differences do not tell: a path tracer's image 2 s after a
  // restart under ThreadSanitizer differed by 0.22 a pixel once, its brightness offset alone by 0.11.
  ASSERT_TRUE(fs::exists(camera_before) && fs::exists(camera_after)) << log;
  EXPECT_EQ(slurp(camera_before), slurp(camera_after));
  EXPECT_GT(block_correlation(a, b, 10), 0.5);
  EXPECT_GT(block_difference(a, b, 10), 0.01);      // light bounces: another integrator (0.11 here)
  EXPECT_GT(block_difference(b, c, 10), 0.05) << log;  // another scene (0.77 here)
  EXPECT_LT(block_correlation(b, c, 10), 0.5) << log;
  EXPECT_NE(log.find("opened " + mesh), std::string::npos) << log;
}

// A restart (here: hard shadows) keeps what the panels changed in the world (a light's colour).
TEST(Panels, EditsSurviveARestart) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("survive");
  const fs::path before = dir / "before.exr", after = dir / "after.exr";
  std::string log;
  const int status = run_viewer_script(
      "default --size 160x100 --threads 2",
      "0.1 key O\n1.2 screenshot " + before.string() + "\n1.3 set light0.color 0.05 0.05 1\n" +
          "1.4 set shadows hard\n3.2 screenshot " + after.string() + "\n3.3 quit\n",
      dir, &log);
  ASSERT_EQ(status, 0) << log;
  ASSERT_NE(log.find("shadows hard (render threads restarted)"), std::string::npos) << log;
  const ExrImage a = screenshot(before, log), b = screenshot(after, log);
  auto ratio = [](const ExrImage& e) { return channel_mean(e, "B", 0, e.width) / channel_mean(e, "R", 0, e.width); };
  EXPECT_GT(ratio(b), 1.3 * ratio(a)) << ratio(a) << " -> " << ratio(b);  // still blue after the restart
}

TEST(Panels, TransferFunctionControlsChangeTheVolume) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("volume");
  const fs::path grey = dir / "grey.exr", clear = dir / "clear.exr", hot = dir / "hot.exr";
  std::string log;
  const int status = run_viewer_script(
      "volume:shepp-logan:48:direct --size 160x120 --threads 2",
      "0.1 key O\n2.0 screenshot " + grey.string() + "\n2.1 panel volumes\n" +
          "2.2 set volume0.points 0 1 1 1 0 1 1 1 1 0\n2.3 key TAB\n4.3 screenshot " + clear.string() +
          "\n4.4 set volume0.preset hot\n6.8 screenshot " + hot.string() + "\n6.9 quit\n",
      dir, &log);
  ASSERT_EQ(status, 0) << log;
  const ExrImage a = screenshot(grey, log), b = screenshot(clear, log), c = screenshot(hot, log);
  EXPECT_GT(mean_difference(a, b), 0.02) << log;  // fully transparent: the phantom is gone
  EXPECT_GT(mean_difference(b, c), 0.02) << log;  // the hot preset shows it again, in colour
  // The preset turns the image toward red: judged by the change from the clear image, which holds
  // while pixels still fill in (under a loaded CI only a quarter had: R 0.561 < B 0.569 yet).
  auto red_minus_blue = [](const ExrImage& e) { return channel_mean(e, "R", 0, e.width) - channel_mean(e, "B", 0, e.width); };
  EXPECT_GT(red_minus_blue(c) - red_minus_blue(b), 0.02) << red_minus_blue(b) << " -> " << red_minus_blue(c);
  EXPECT_NE(log.find("transfer function hot"), std::string::npos) << log;
}

TEST(Panels, SaveCaptureAndCameraPathWriteTheirFiles) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("files");
  const fs::path snaps = dir / "snaps", path = dir / "path.json";
  std::string log;
  const int status = run_viewer_script(
      "default --size 120x80 --threads 1 --snapshot-dir " + snaps.string(),
      // The capture goes on across a restart of the session (hard shadows: a new engine and display).
      "0.5 set save png\n0.6 set save exr\n0.7 set capture on\n0.8 orbit 40 0\n1.0 orbit 40 0\n"
      "1.2 set shadows hard\n2.2 set capture off\n2.3 set camera.save " + path.string() + "\n2.4 quit\n",
      dir, &log);
  ASSERT_EQ(status, 0) << log;
  EXPECT_TRUE(fs::exists(snaps / "snapshot_000.png")) << log;
  EXPECT_TRUE(fs::exists(snaps / "snapshot_000.exr")) << log;
  size_t frames = 0;
  for (const auto& e : fs::directory_iterator(snaps / "window_capture_000")) frames += e.path().extension() == ".png";
  EXPECT_GE(frames, 5u) << log;  // a second at 60 Hz, however loaded the machine
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex("captured (\\d+) frames"))) << log;
  EXPECT_EQ(std::stoul(m[1]), frames);
  EXPECT_EQ(log.find("capture stopped"), std::string::npos) << log;
  auto p = load_camera_path(path.string());
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_GE(p->keyframes.size(), 3u);  // the start and both orbits
}

// The error plot: a reference of the view rendered beside the engine, then the displayed image's
// RMSE against it while the camera stays, small once the image has converged.
TEST(Panels, ErrorPlotComparesAgainstAReferenceOfTheView) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("error");
  std::string log;
  const int status = run_viewer_script("default --size 96x64 --threads 1",
                                       // 16 spp: ready in about a second even under ASan with a parallel ctest.
                                       "0.05 set reference 16\n0.1 panel plots\n6.0 quit\n", dir, &log);
  ASSERT_EQ(status, 0) << log;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex("RMSE against the reference of the view: ([0-9.]+) first, ([0-9.]+) last \\((\\d+) points\\)"))) << log;
  EXPECT_GE(std::stoul(m[3]), 4u);
  EXPECT_LT(std::stod(m[2]), 0.05) << log;  // a converged image is close to the reference
  EXPECT_GT(std::stod(m[2]), 0.0) << log;   // measured, not a constant (a black reference gives ~0.5)
}

// A reference renders the scene as loaded: after an edit of the world it is refused in one line,
// and one being rendered when the world changes is dropped.
TEST(Panels, AReferenceIsNeverComparedWithAnEditedWorld) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb)";
  const fs::path dir = folder("stale");
  std::string log;
  const int status = run_viewer_script(
      "default --size 96x64 --threads 1",
      "0.05 set reference 16\n0.06 set light0.color 1 0.2 0.2\n1.5 set reference 16\n3.0 quit\n", dir, &log);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(log.find("reference: the lights, materials or objects were edited"), std::string::npos) << log;
  EXPECT_EQ(log.find("RMSE against the reference"), std::string::npos) << log;  // nothing compared
}

// Dropping a volume file on the window opens it as a scene of its own.
TEST(Panels, VolumeFilesOpenAsScenes) {
  auto s = load_scene(std::string(FRAMELESS_TEST_DATA) + "/volumes/sphere_ls_blosc.vdb");
  ASSERT_TRUE(s.ok()) << s.error().message;
  ASSERT_EQ(s.value()->volumes.size(), 1u);
  EXPECT_EQ(s.value()->volumes[0].mode, VolumeMode::kIsosurface);  // a level set: its surface
  EXPECT_TRUE(camera_is_valid(s.value()->camera));
  auto fog = load_scene(std::string(FRAMELESS_TEST_DATA) + "/volumes/fog_zip.vdb");
  ASSERT_TRUE(fog.ok()) << fog.error().message;
  EXPECT_NE(fog.value()->volumes[0].mode, VolumeMode::kIsosurface);  // densities: the volume shader
  const fs::path bad = folder("vdb") / "bad.vdb";
  std::ofstream(bad) << "not a vdb";
  auto r = load_scene(bad.string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
  EXPECT_NE(r.error().message.find("bad.vdb"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace frameless
