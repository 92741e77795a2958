// The engine and blend flags that view and capture share: a bad value of the motion settings is
// a one-line error with a non-zero exit, and the capture writes nothing.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

TEST(EngineFlagsCli, BadMotionSettingsAreOneLineErrors) {
  struct Case {
    const char* args;
    const char* expect;
  };
  for (const Case& c : {Case{"--reproject-budget 2", "--reproject-budget"},
                        Case{"--reproject-budget -0.5", "--reproject-budget"},
                        Case{"--max-samples-per-s -5", "--max-samples-per-s"},
                        Case{"--render-nice 20", "--render-nice"}, Case{"--render-nice -1", "--render-nice"}}) {
    SCOPED_TRACE(c.args);
    const auto dir = fresh_dir("engine_flags_bad");
    const auto out = dir / "capture";
    const CommandResult r = run_frameless(std::string("capture default --size 16x16 --duration 0.1 ") +
                                          c.args + " --out " + out.string());
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_LT(r.exit_code, 128) << "crashed: " << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

// The settings run: a capped, budgeted capture with render threads at nice 5 still writes its frames.
TEST(EngineFlagsCli, CappedBudgetedCaptureWritesItsFrames) {
  const auto dir = fresh_dir("engine_flags_ok");
  const auto out = dir / "capture";
  const CommandResult r = run_frameless(
      "capture default --size 32x24 --duration 0.3 --refresh 20 --no-mp4 --orbit 20 "
      "--reproject-budget 0.2 --max-samples-per-s 20000 --render-nice 5 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(out / "manifest.json")) << r.output;
}

}  // namespace
}  // namespace frameless::test
