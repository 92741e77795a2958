// tools/ab_bench.py end to end: two "builds" (wrappers around this build's binary that log each
// run, the second moving the camera four times as far) compared on bench reproject's figures that
// do not depend on timing, so the medians, ratios and counts are known; the runs alternate A B B A;
// the sign test's p of each count; bad input is one line and exit code 2. (No timing is asserted.)
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

const std::string kTool = std::string(FRAMELESS_TEST_DATA) + "/../../tools/ab_bench.py";
const std::string kBench = "bench reproject default --size 96x54 --changes 2 --order curve";

CommandResult run_tool(const std::string& args) { return run_command("/usr/bin/python3 " + kTool + " " + args); }

// A wrapper that appends `name` to `log` and runs this build's frameless with `extra` after the
// arguments it is given.
std::string wrapper(const std::filesystem::path& dir, const std::string& name, const std::string& extra) {
  const std::filesystem::path path = dir / name;
  std::ofstream(path) << "#!/bin/sh\nprintf " << name << " >> " << (dir / "log").string() << "\nexec "
                      << FRAMELESS_BINARY << " \"$@\" " << extra << "\n";
  ::chmod(path.c_str(), 0755);
  return path.string();
}

// The whitespace-separated cells of the report's row for `field`.
std::vector<std::string> row(const std::string& report, const std::string& field) {
  std::istringstream lines(report);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream cells(line);
    std::vector<std::string> out;
    for (std::string c; cells >> c;) out.push_back(c);
    if (!out.empty() && out[0] == field) return out;
  }
  return {};
}

TEST(AbBench, AlternatesTheSidesAndComparesMedians) {
  const auto dir = fresh_dir("ab_bench");
  const std::string a = wrapper(dir, "A", ""), b = wrapper(dir, "B", "--degrees 2");
  const CommandResult r = run_tool("--rounds 3 --field curve_order.moved_fraction --field curve_order.disoccluded_fraction "
                                   "--field changes " + a + " " + b + " -- " + kBench);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream log(dir / "log");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(log), {}), "ABBAAB");  // a drift falls on both sides alike
  // A's median is A's figure (the move is deterministic); a farther move moves fewer pixels and
  // uncovers more, in every round.
  const CommandResult direct = run_frameless(kBench + " --json");
  ASSERT_EQ(direct.exit_code, 0) << direct.output;
  const double moved = nlohmann::json::parse(direct.output)["curve_order"]["moved_fraction"].get<double>();
  const std::vector<std::string> m = row(r.output, "curve_order.moved_fraction");
  const std::vector<std::string> d = row(r.output, "curve_order.disoccluded_fraction");
  const std::vector<std::string> c = row(r.output, "changes");
  ASSERT_EQ(m.size(), 8u) << r.output;  // figure, A, B, B / A, k "of" n, p
  ASSERT_EQ(d.size(), 8u) << r.output;
  ASSERT_EQ(c.size(), 8u) << r.output;
  EXPECT_NEAR(std::stod(m[1]), moved, 1e-3 * moved) << r.output;
  EXPECT_NEAR(std::stod(m[3]), std::stod(m[2]) / std::stod(m[1]), 2e-3) << r.output;
  EXPECT_LT(std::stod(m[3]), 1.0) << r.output;
  EXPECT_EQ(m[4] + " " + m[5] + " " + m[6], "0 of 3") << r.output;
  EXPECT_GT(std::stod(d[3]), 1.0) << r.output;
  EXPECT_EQ(d[4] + " " + d[5] + " " + d[6], "3 of 3") << r.output;
  // The sign test, two-sided: 0 or 3 of 3 rounds is a chance of 2 / 8 under no difference; a
  // figure both sides share (the number of changes) ties every round, which is no evidence: 1.
  EXPECT_EQ(m[7], "0.250") << r.output;
  EXPECT_EQ(d[7], "0.250") << r.output;
  EXPECT_EQ(c[4] + " " + c[5] + " " + c[6] + " " + c[7], "0 of 3 1.000") << r.output;
  std::filesystem::remove_all(dir);
}

TEST(AbBench, BadInputIsOneLineAndExitsTwo) {
  const std::string bin = FRAMELESS_BINARY;
  for (const std::string& args : {"--field nope " + bin + " " + bin + " -- " + kBench,   // no such figure
                                  bin + " /no/such/frameless -- " + kBench,              // no binary
                                  bin + " " + bin + " -- bench reproject no_such_scene",  // the bench fails
                                  "--env-a NOEQUALS " + bin + " " + bin + " -- " + kBench,
                                  "--rounds 0 " + bin + " " + bin + " -- " + kBench, bin + " " + bin,
                                  std::string("--bogus ") + bin + " " + bin + " -- " + kBench}) {
    SCOPED_TRACE(args);
    const CommandResult r = run_tool(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_EQ(r.output.rfind("ab_bench: ", 0), 0u) << r.output;
  }
}

// Benchmarks whose output changes from run to run: a figure missing in a later round only (a
// rate over no rays is written as null), and outputs with no number in common, are one line too.
TEST(AbBench, FiguresMissingInALaterRoundOrNotSharedAreOneLine) {
  const auto dir = fresh_dir("ab_bench_outputs");
  const auto script = [&](const std::string& name, const std::string& body) {
    const std::filesystem::path path = dir / name;
    std::ofstream(path) << "#!/bin/sh\n" << body << "\n";
    ::chmod(path.c_str(), 0755);
    return path.string();
  };
  // The first run prints x and y, every later one x alone.
  const std::string once = script("once", "if [ -e " + (dir / "ran").string() + " ]; then echo '{\"x\": 1}'; else touch " +
                                              (dir / "ran").string() + "; echo '{\"x\": 1, \"y\": 2}'; fi");
  const std::string both = script("both", "echo '{\"x\": 1, \"y\": 3}'");
  CommandResult r = run_tool("--rounds 2 --field y " + once + " " + both + " -- bench");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output, "ab_bench: A's output has no number 'y' in round 2\n");
  r = run_tool("--rounds 2 --field x " + once + " " + both + " -- bench");  // x is in every round
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = run_tool("--rounds 1 " + script("text_a", "echo '{\"a\": \"x\"}'") + " " +
               script("text_b", "echo '{\"b\": [\"y\"]}'") + " -- bench");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output, "ab_bench: A's and B's outputs share no number to compare\n");
  r = run_tool("--rounds 1 " + script("binary", "printf '\\377\\376{'") + " " + both + " -- bench");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("is not JSON"), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace frameless::test
