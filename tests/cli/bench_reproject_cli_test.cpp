// `frameless bench reproject --json` end to end on a small image: all three orders measured, the
// image moved as an orbit of half a degree moves it (most pixels land somewhere, few are
// uncovered; 1280x720 gives 78 % and 4 %), its phases reported (slot order's gather in two
// passes along the curve and in slot order), the change also in copies of the image's pixels (that
// machine's memory speed), bad arguments one line each. (No timing is asserted.)
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

TEST(BenchReprojectCli, JsonReportsEveryOrderAndAPlausibleMove) {
  const CommandResult r = run_frameless("bench reproject default --size 160x90 --changes 3 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  // Which vector paths ran (their costs differ by machine).
  const std::string paths = j.value("vector_paths", "");
  EXPECT_TRUE(paths == "AVX-512" || paths == "AVX2" || paths == "scalar") << r.output;
  // The machine's copy of an image's pixels, the unit a change is also given in.
  const double copy_ms = j.value("image_copy_ms", 0.0);
  EXPECT_GT(copy_ms, 0.0) << r.output;
  EXPECT_NEAR(j.value("image_copy_gb_per_s", 0.0), 2.0 * 160 * 90 * 16 / (copy_ms * 1e6), 1e-6 * j.value("image_copy_gb_per_s", 0.0));
  for (const char* order : {"curve_order", "slot_order", "pixel_order"}) {
    ASSERT_TRUE(j.contains(order)) << r.output;
    EXPECT_GT(j[order]["median_ms"].get<double>(), 0.0);
    EXPECT_NEAR(j[order]["image_copies"].get<double>(), j[order]["median_ms"].get<double>() / copy_ms,
                1e-9 * j[order]["image_copies"].get<double>()) << order;
    EXPECT_GT(j[order]["moved_fraction"].get<double>(), 0.5) << r.output;  // the rest: cracks closed, a band uncovered
    EXPECT_LT(j[order]["disoccluded_fraction"].get<double>(), 0.2) << r.output;
    for (const char* phase : {"splat", "cracks", "disocclusions", "pixel_pass", "slot_pass"})
      EXPECT_GE(j[order]["phases_ms"][phase].get<double>(), 0.0) << order << " " << phase;
    EXPECT_GT(j[order]["phases_ms"]["pixel_pass"].get<double>(), 0.0) << r.output;
  }
  // The curve and slot order gather in two passes; pixel order in one.
  EXPECT_GT(j["curve_order"]["phases_ms"]["slot_pass"].get<double>(), 0.0) << r.output;
  EXPECT_GT(j["slot_order"]["phases_ms"]["slot_pass"].get<double>(), 0.0) << r.output;
  EXPECT_EQ(j["pixel_order"]["phases_ms"]["slot_pass"].get<double>(), 0.0) << r.output;
  // The order changes where pixels live, not what moves where.
  EXPECT_EQ(j["slot_order"]["moved_fraction"], j["pixel_order"]["moved_fraction"]);
  EXPECT_EQ(j["curve_order"]["moved_fraction"], j["pixel_order"]["moved_fraction"]);
  const CommandResult one = run_frameless("bench reproject default --size 160x90 --changes 2 --order pixels --json");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_FALSE(nlohmann::json::parse(one.output).contains("slot_order"));
  EXPECT_FALSE(nlohmann::json::parse(one.output).contains("curve_order"));
  EXPECT_EQ(nlohmann::json::parse(one.output)["evict_mb"], 0);
  // Other memory written between changes moves the same pixels.
  const CommandResult evicted =
      run_frameless("bench reproject default --size 160x90 --changes 2 --order pixels --evict 2 --json");
  ASSERT_EQ(evicted.exit_code, 0) << evicted.output;
  const nlohmann::json e = nlohmann::json::parse(evicted.output);
  EXPECT_EQ(e["evict_mb"], 2);
  EXPECT_EQ(e["pixel_order"]["moved_fraction"], nlohmann::json::parse(one.output)["pixel_order"]["moved_fraction"]);
}

TEST(BenchReprojectCli, BadArgumentsAreOneLine) {
  for (const char* args : {"bench reproject --order diagonal", "bench reproject --changes 0",
                           "bench reproject --degrees 90", "bench reproject --size 0x5", "bench reproject --evict -1",
                           "bench reproject --evict 4096",
                           "bench reproject no_such_scene.json"}) {
    const CommandResult r = run_frameless(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace frameless::test
