// tools/ray_instructions.py: a callgrind output file read into calls and costs per call, ours
// against Embree (only the bench's own calls count, each with the cost callgrind recorded at its
// call site); bad input is one line and exit code 2; under valgrind, where this build can
// run there (no AVX-512), the same rays are counted end to end. (No timing is asserted.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

const std::string kTool = std::string(FRAMELESS_TEST_DATA) + "/../../tools/ray_instructions.py";

CommandResult run_tool(const std::string& args) { return run_command("/usr/bin/python3 " + kTool + " " + args); }

// A walk called twice from the bench (and once from itself, through an instance: not a call of
// its own), Embree's closest-hit query three times and its any-hit query four times; the any-hit
// walk only from a packet's fallback, which the bench did not call ray by ray.
constexpr const char* kProfile = R"(# callgrind format
version: 1
creator: a test
positions: line
events: Ir Bc Bcm
summary: 5000 300 30

fl=(1) bench_rays.cpp
fn=(1) frameless::bench::rays_of_scene(frameless::bench::RaysOptions const&)
10 50 5 1
cfl=(2) accel.cpp
cfn=(2) frameless::Accel::intersect(frameless::Ray const&, frameless::Hit&, frameless::InstanceTop const*) const
calls=2 100
12 1300 80 6
cfn=(3) rtcIntersect1
calls=3 0
+2 1350 120 12
cfn=(4) rtcOccluded1
calls=4 0
* 1600 100 8

fl=(2)
fn=(2)
100 1000 60 4
cfn=(2)
calls=1 100
+2 200 10 1
fn=(5) frameless::Accel::occluded_packet(frameless::Ray const*, int, bool*, frameless::InstanceTop const*) const
200 30 2 0
cfn=(6) frameless::Accel::occluded(frameless::Ray const&, frameless::InstanceTop const*) const
calls=5 300
202 2500 150 9
)";

std::string write_profile(const std::string& name, const std::string& text) {
  const auto path = fresh_dir("ray_instructions") / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(RayInstructions, CountsCallsFromOutsideAndTheirCostsPerCall) {
  const std::string profile = write_profile("callgrind.out", kProfile);
  const CommandResult r = run_tool("--json --parse " + profile);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  const nlohmann::json& calls = j["calls"];
  // The walk's call of itself is inside its two calls' costs, not a third call.
  EXPECT_EQ(calls["ours_intersect"]["calls"].get<int>(), 2);
  EXPECT_DOUBLE_EQ(calls["ours_intersect"]["per_call"]["Ir"].get<double>(), 650.0);
  EXPECT_DOUBLE_EQ(calls["ours_intersect"]["per_call"]["Bcm"].get<double>(), 3.0);
  EXPECT_EQ(calls["embree_intersect"]["calls"].get<int>(), 3);
  EXPECT_DOUBLE_EQ(calls["embree_intersect"]["per_call"]["Ir"].get<double>(), 450.0);
  EXPECT_DOUBLE_EQ(calls["embree_intersect"]["per_call"]["Bc"].get<double>(), 40.0);
  EXPECT_EQ(calls["embree_occluded"]["calls"].get<int>(), 4);
  EXPECT_DOUBLE_EQ(calls["embree_occluded"]["per_call"]["Ir"].get<double>(), 400.0);
  EXPECT_FALSE(calls.contains("ours_occluded"));  // never called by the bench: no row, no ratio
  // The table: each side per call and ours / Embree (650 / 450 instructions, 3 / 4 mispredicted).
  const CommandResult table = run_tool("--parse " + profile);
  ASSERT_EQ(table.exit_code, 0) << table.output;
  std::istringstream lines(table.output);
  std::vector<std::string> ratio_rows;
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("ours / Embree", 0) == 0) ratio_rows.push_back(line);
  ASSERT_EQ(ratio_rows.size(), 1u) << table.output;
  std::istringstream cells(ratio_rows[0].substr(13));
  double instructions = 0, branches = 0, mispredicted = 0;
  cells >> instructions >> branches >> mispredicted;
  EXPECT_DOUBLE_EQ(instructions, 1.444);
  EXPECT_DOUBLE_EQ(branches, 1.0);
  EXPECT_DOUBLE_EQ(mispredicted, 0.75);
}

TEST(RayInstructions, BadInputIsOneLineAndExitsTwo) {
  const std::string garbage = write_profile("garbage.out", "this is no profile\n");
  std::string bad_cost = kProfile;
  bad_cost.replace(bad_cost.find("12 1300 80 6"), 12, "12 1300 x8 6");
  const std::string bad = write_profile("bad_cost.out", bad_cost);
  for (const std::string& args :
       {std::string(""), std::string("--parse /no/such/file"), "--parse " + garbage, "--parse " + bad,
        std::string("/no/such/frameless bunny"), std::string("--size 0x5 ") + FRAMELESS_BINARY,
        "--parse " + garbage + " " + FRAMELESS_BINARY, std::string("--prefetch 2 ") + FRAMELESS_BINARY}) {
    const CommandResult r = run_tool(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
    EXPECT_EQ(r.output.rfind("ray_instructions: ", 0), 0u) << args << ": " << r.output;
  }
}

TEST(RayInstructions, CountsTheRaysOfARunUnderValgrind) {
#if defined(__AVX512F__)
  GTEST_SKIP() << "an AVX-512 build: valgrind does not run it (build with -DFRAMELESS_ARCH=x86-64-v3)";
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "a sanitizer build: valgrind does not run it";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
  GTEST_SKIP() << "a sanitizer build: valgrind does not run it";
#endif
#endif
  if (std::system("command -v valgrind > /dev/null 2>&1") != 0) GTEST_SKIP() << "valgrind is not installed";
  const CommandResult r = run_tool(std::string("--json --prefetch 0 --size 16x16 ") + FRAMELESS_BINARY + " spheres:2000");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  EXPECT_EQ(j["scene"].get<std::string>(), "spheres:2000");
  const nlohmann::json& ours = j["calls"]["ours_intersect"];
  EXPECT_GE(ours["calls"].get<int>(), 256);  // at least the 16x16 primary rays
  EXPECT_GT(ours["per_call"]["Ir"].get<double>(), 20.0);
  EXPECT_GT(ours["per_call"]["Bc"].get<double>(), 1.0);
  if (j["calls"].contains("embree_intersect")) EXPECT_GE(j["calls"]["embree_intersect"]["calls"].get<int>(), 256);
}

}  // namespace
}  // namespace frameless::test
