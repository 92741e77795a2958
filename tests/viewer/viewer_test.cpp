// The viewer for real: under Xvfb the window opens, shows the scene, reacts to a scripted camera
// move and quits cleanly; without a display it says so in one line; scripts are validated.
#include "viewer/viewer.h"

#include <gtest/gtest.h>

#include "display/camera_path.h"
#include "viewer_test_util.h"

namespace frameless {
namespace {

[[maybe_unused]] ::testing::Environment* const cleanup =
    ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

TEST(Viewer, SmokeTestUnderXvfb) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb): viewer smoke test skipped";
  const fs::path dir = scratch();
  const fs::path before = dir / "before.exr", after = dir / "after.exr", rec = dir / "rec.json";
  // Wall-clock times: generous gaps so a loaded machine (or ASan) still gets there.
  // Overlay off (O) so live figures in the text do not count as change: without the move the two
  // screenshots differ by ~0.0003 on average, with it by ~0.25.
  std::ofstream(dir / "script.txt") << "0.1 key O\n"
                                    << "1.5 screenshot " << before.string() << "\n"
                                    << "1.6 orbit 200 30\n"
                                    << "1.7 zoom 2\n"
                                    << "3.5 screenshot " << after.string() << "\n"
                                    << "3.6 quit\n";
  const std::string cmd = std::string(kChildLeakCheck) +
                          "xvfb-run -a -s '-screen 0 320x240x24' " + std::string(FRAMELESS_BINARY) +
                          " view --size 96x64 --threads 2 --script " + (dir / "script.txt").string() +
                          " --record " + rec.string() + " > " + (dir / "log.txt").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_EQ(status, 0) << slurp(dir / "log.txt");  // quits cleanly on the script's command
  auto a = read_exr(before.string()), b = read_exr(after.string());
  ASSERT_TRUE(a.ok() && b.ok()) << slurp(dir / "log.txt");
  EXPECT_EQ(a->width, 96);
  EXPECT_EQ(a->height, 64);
  // The scene is shown: many colours, not one background colour (an empty window has 1-2).
  EXPECT_GT(distinct_colours(*a), 100u);
  // The camera move changed the picture.
  EXPECT_GT(mean_difference(*a, *b), 0.02);
  EXPECT_EQ(mean_difference(*a, *a), 0.0);
  // The recording replays: keyframes from the start pose to the moved one.
  auto path = load_camera_path(rec.string());
  ASSERT_TRUE(path.ok()) << path.error().message;
  ASSERT_GE(path->keyframes.size(), 3u);
  EXPECT_NE(path->keyframes.front().camera.eye, path->keyframes.back().camera.eye);
}

TEST(Viewer, VolumeKeysMoveTheIsovalueUnderXvfb) {
  if (!have("xvfb-run")) GTEST_SKIP() << "xvfb-run is not installed (apt-get install xvfb): viewer volume test skipped";
  const fs::path dir = scratch();
  const fs::path before = dir / "before.exr", after = dir / "after.exr", same = dir / "same.exr";
  // X five times raises the sphere's isovalue by 10 % of the distance range: a bigger sphere.
  // B (no volume-shader volume here) changes nothing: two screenshots around it stay alike.
  std::ofstream(dir / "script.txt") << "0.1 key O\n"
                                    << "1.2 screenshot " << before.string() << "\n"
                                    << "1.3 key B\n"
                                    << "2.4 screenshot " << same.string() << "\n"
                                    << "2.5 key X\n2.55 key X\n2.6 key X\n2.65 key X\n2.7 key X\n"
                                    << "4.0 screenshot " << after.string() << "\n"
                                    << "4.1 quit\n";
  const std::string cmd = std::string(kChildLeakCheck) + "xvfb-run -a -s '-screen 0 320x240x24' " +
                          std::string(FRAMELESS_BINARY) + " view volume:sphere:24 --size 96x64 --threads 2 --script " +
                          (dir / "script.txt").string() + " > " + (dir / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "log.txt");
  auto a = read_exr(before.string()), b = read_exr(after.string()), c = read_exr(same.string());
  ASSERT_TRUE(a.ok() && b.ok() && c.ok()) << slurp(dir / "log.txt");
  EXPECT_LT(mean_difference(*a, *c), 0.01);  // B: nothing to switch
  EXPECT_GT(mean_difference(*a, *b), 0.02);  // X: the surface moved
}

TEST(Viewer, NoDisplayIsOneClearLine) {
  const fs::path dir = scratch();
  const std::string cmd = "env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(FRAMELESS_BINARY) +
                          " view --size 32x32 > " + (dir / "out.txt").string() + " 2> " +
                          (dir / "err.txt").string();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << "crashed";
  EXPECT_EQ(WEXITSTATUS(status), 3);
  const std::string err = slurp(dir / "err.txt");
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("frameless capture"), std::string::npos) << err;
}

TEST(Viewer, ScriptsAreValidatedWithFileAndLine) {
  auto ok = parse_viewer_script("# c\n2 quit\n0.5 orbit 10 -3\n1 key M\n", "s.txt");
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  ASSERT_EQ(ok->size(), 3u);
  EXPECT_EQ((*ok)[0].command, "orbit");  // sorted by time
  EXPECT_EQ((*ok)[2].command, "quit");
  for (const char* bad : {"x quit", "1 dance", "1 orbit 3", "1 key NOPE", "-1 quit", "1"}) {
    auto r = parse_viewer_script(std::string("0 quit\n") + bad + "\n", "s.txt");
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().message.rfind("s.txt:2: ", 0), 0u) << r.error().message;
  }
}

}  // namespace
}  // namespace frameless
