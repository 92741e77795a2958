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

// With Embree in the build, instanced scenes are instanced on Embree's side too (its own instance
// geometry over each mesh's scene), and the two agree on what each primary ray hits: the same
// instance and primitive. A transform handed over in the wrong layout, or an instance numbered
// apart from ours, breaks the agreement.
TEST(BenchRaysCli, EmbreeSeesTheSameInstances) {
  const CommandResult r = run_frameless("bench rays sunflowers:1 --opaque --size 48x48 --reps 1 --threads 1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  if (!j.contains("embree")) GTEST_SKIP() << "this build has no Embree (tools/install-deps.sh --bench)";
  ASSERT_GT(j["instances"].get<int>(), 1);
  EXPECT_GT(j["primary_hit_fraction"].get<double>(), 0.5);
  // Rays exactly on a shared edge may go to either triangle: allow one in a hundred.
  EXPECT_GE(j["embree"]["primary_agreement"].get<double>(), 0.99);
  EXPECT_GE(j["embree"]["shadow_agreement"].get<double>(), 0.99);
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
