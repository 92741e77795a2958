// `frameless bench build --json` end to end on small scenes: the keys are there with sane values,
// the parallel build gave the serial tree, and bad arguments get a one-line error. (No timing is
// asserted.)
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

TEST(BenchBuildCli, JsonHasTheKeysAndTheSameTree) {
  for (const char* flags : {"", " --shuffle"}) {
    const CommandResult r = run_frameless(
        std::string("bench build default spheres:70000 --json --threads 2 --reps 1") + flags);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << r.output;
    ASSERT_TRUE(j.is_array());
    ASSERT_EQ(j.size(), 2u);
    EXPECT_EQ(j[0]["scene"], "default");
    EXPECT_EQ(j[1]["spheres"], 70000);
    for (const auto& s : j) {
      for (const char* k : {"build_ms_1t", "build_ms_nt", "nodes", "depth", "sah_cost"})
        ASSERT_TRUE(s.contains(k)) << k;
      EXPECT_GE(s["build_ms_1t"].get<double>(), 0.0);
      EXPECT_GT(s["nodes"].get<int>(), 0);
      EXPECT_GT(s["sah_cost"].get<double>(), 1.0);
      EXPECT_EQ(s["parallel_tree_identical"], true);
      EXPECT_EQ(s["threads"], 2);
      if (s.contains("embree")) {
        EXPECT_GT(s["embree"]["ratio_1t"].get<double>(), 0.0);
        EXPECT_GT(s["embree"]["ratio_nt"].get<double>(), 0.0);
      }
    }
  }
}

TEST(BenchBuildCli, BadArgumentsAreOneLine) {
  for (const char* args : {"bench build default --reps 0", "bench build default --threads -2",
                           "bench build no_such_scene.json"}) {
    const CommandResult r = run_frameless(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace frameless::test
