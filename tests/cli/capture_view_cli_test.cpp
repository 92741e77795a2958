// The capture and view commands refuse bad output folders and views in one line (the library
// side of both is tested in tests/display).
#include <fstream>

#include <gtest/gtest.h>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

TEST(CaptureCli, AnUnwritableFolderIsOneLineAndAFailure) {
  const auto dir = fresh_dir("capture_unwritable");
  const std::string file = (dir / "a_file").string();
  std::ofstream(file) << "x";
  // A folder below a regular file cannot exist, whoever runs the test (root included).
  const CommandResult r = run_frameless("capture --size 16x16 --duration 0.1 --out " + file + "/out");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("frameless: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
}

TEST(ViewCli, AnUnknownViewIsOneLineBeforeADisplayIsNeeded) {
  const CommandResult r = run_frameless("view --view depth");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.output.rfind("frameless: --view: unknown view 'depth'", 0), 0u) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
}

}  // namespace
}  // namespace frameless::test
