// `frameless bench engine --json` end to end on a tiny run: the keys the engine issue names are
// there with sane values, and bad arguments get a one-line error. (No timing is asserted.)
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

TEST(BenchCli, EngineJsonHasTheNamedKeys) {
  const CommandResult r = run_frameless(
      "bench engine default --json --size 64x48 --threads 2 --seconds 0.2 --repeats 1 --moving-sizes 96x64");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  for (const char* k : {"frameless_samples_per_s", "conventional_samples_per_s",
                        "display_cpu_fraction", "latency_ms", "latency_ideal_ms",
                        "display_ns_per_update", "consumer_cpu_fraction"})
    ASSERT_TRUE(j.contains(k)) << k;
  EXPECT_GT(j["frameless_samples_per_s"].get<double>(), 0.0);
  EXPECT_GT(j["conventional_samples_per_s"].get<double>(), 0.0);
  // A fraction of one core (0 when no display tick ended inside the short window: a loaded
  // machine or a sanitizer build; speed is the benchmark's business, not this test's).
  const double cpu = j["display_cpu_fraction"].get<double>();
  EXPECT_GE(cpu, 0.0);
  EXPECT_LT(cpu, 1.0);
  const auto& l = j["latency_ms"];
  const double p50 = l["p50"].get<double>(), p95 = l["p95"].get<double>(),
               p100 = l["p100"].get<double>();
  EXPECT_GT(p50, 0.0);
  EXPECT_LE(p50, p95);
  EXPECT_LE(p95, p100);
  EXPECT_GT(j["latency_ideal_ms"].get<double>(), 0.0);
  // The further size of --moving-sizes, measured with reprojection on.
  ASSERT_EQ(j["display_moving_reproject_by_size"].size(), 1u) << r.output;
  const auto& m = j["display_moving_reproject_by_size"][0];
  EXPECT_EQ(m["width"], 96);
  EXPECT_EQ(m["height"], 64);
  EXPECT_GE(m["display_cpu_fraction"].get<double>(), 0.0);
  EXPECT_LT(m["display_cpu_fraction"].get<double>(), 1.0);
  EXPECT_GE(m["reprojections_per_s"].get<double>(), 0.0);
  // Its phases: the gather goes by pixel, then by slot (the engine's layout is shuffled chunks).
  for (const char* phase : {"splat", "cracks", "disocclusions", "pixel_pass", "slot_pass"}) {
    EXPECT_GE(m["phases_wall_ms"][phase].get<double>(), 0.0) << phase << " " << r.output;
    EXPECT_GE(m["phases_cpu_ms"][phase].get<double>(), 0.0) << phase << " " << r.output;
  }
  if (m["reprojections_per_s"].get<double>() > 0) {
    EXPECT_GT(m["phases_wall_ms"]["slot_pass"].get<double>(), 0.0);
    EXPECT_GT(m["phases_cpu_ms"]["slot_pass"].get<double>(), 0.0);
  }
  EXPECT_EQ(j["width"], 64);
  EXPECT_EQ(j["threads"], 2);
}

TEST(BenchCli, EngineBadArgumentsAreOneLine) {
  for (const char* args : {"bench engine --size 0x48", "bench engine --seconds -1", "bench engine --budget 0",
                           "bench engine --budget 2", "bench engine --render-nice 20", "bench engine no_such_scene.json",
                           "bench engine --moving-sizes 640x0", "bench engine --moving-sizes 640x360 big"}) {
    const CommandResult r = run_frameless(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
  }
}

// Checked before anything is run or written: no output directory appears.
TEST(BenchCli, MotionBadArgumentsAreOneLine) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "frameless_motion_bad_args";
  std::filesystem::remove_all(out);
  for (const std::string flags :
       {"--budget 0", "--budget 1.5", "--budget nan", "--budget x", "--render-nice 20", "--render-nice -3"}) {
    const CommandResult r = run_frameless("bench motion --quick " + flags + " --out " + out.string());
    EXPECT_NE(r.exit_code, 0) << flags;
    EXPECT_EQ(count_lines(r.output), 1) << flags << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << flags;
  }
}

}  // namespace
}  // namespace frameless::test
