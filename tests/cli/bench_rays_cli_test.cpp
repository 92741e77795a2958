// `frameless bench rays --json` end to end on a small image: the work per ray (8-wide nodes
// entered, primitives tested) is reported for every kind of ray, and the BVH keeps it to a tiny
// fraction of the scene; bad arguments are one line each. (No timing is asserted.)
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

TEST(BenchRaysCli, JsonReportsTheWorkOfEachKindOfRay) {
  const CommandResult r =
      run_frameless("bench rays spheres:20000 --size 64x64 --reps 1 --threads 1 --json --no-embree");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  ASSERT_EQ(j["prims"].get<double>(), 20000.0);
  for (const char* kind : {"primary", "shadow", "bounce", "bounce_shadow"}) {
    ASSERT_TRUE(j["work_per_ray"].contains(kind)) << r.output;
    const double nodes = j["work_per_ray"][kind]["nodes"], prims = j["work_per_ray"][kind]["prims"];
    EXPECT_GE(nodes, 1.0) << kind;  // every ray enters the root
    EXPECT_GT(prims, 0.0) << kind;
    // A tree over 20000 spheres: a ray visits a few dozen nodes and tests a few dozen spheres,
    // not a linear share of them.
    EXPECT_LT(nodes, 60.0) << kind;
    EXPECT_LT(prims, 200.0) << kind;
  }
}

TEST(BenchRaysCli, BadArgumentsAreOneLine) {
  for (const char* args : {"bench rays --reps 0", "bench rays --size 0x5", "bench rays --threads -2",
                           "bench rays no_such_scene.json"}) {
    const CommandResult r = run_frameless(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace frameless::test
