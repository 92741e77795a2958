// Volumes from the command line: every built-in volume scene renders and captures (both engine
// modes, deterministic captures bit-identical), `bench volume --quick --json` reports its figures,
// and bad volume names, NRRD and raw files stop with one line and no output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;
using namespace frameless::test;

TEST(VolumeCli, BuiltInVolumesRenderInEveryModeAndEngineMode) {
  const auto dir = fresh_dir("volume_cli");
  for (const char* scene : {"volume:sphere:20", "volume:marschner-lobb:17:direct", "volume:shepp-logan:24:mip"}) {
    const CommandResult r = run_frameless(std::string("render ") + scene + " --size 32x32 --spp 1 --out " +
                                          (dir / "r.exr").string());
    EXPECT_EQ(r.exit_code, 0) << scene << ": " << r.output;
    for (const char* mode : {"frameless", "conventional"}) {
      const auto out = dir / (std::string("cap_") + mode);
      const CommandResult c = run_frameless(std::string("capture ") + scene + " --mode " + mode +
                                            " --deterministic --size 32x32 --refresh 10 --duration 0.2 "
                                            "--samples-per-tick 2048 --no-mp4 --no-contact-sheet --out " +
                                            out.string());
      EXPECT_EQ(c.exit_code, 0) << scene << " " << mode << ": " << c.output;
      EXPECT_TRUE(fs::exists(out / "frame_00001.exr")) << scene << " " << mode;
    }
  }
}

TEST(VolumeCli, BenchVolumeQuickReportsEveryMode) {
  const auto dir = fresh_dir("volume_bench");
  const CommandResult r = run_frameless("bench volume --quick --json --threads 2 --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  for (const char* mode : {"isosurface", "direct", "mip"}) {
    const auto& m = j.at("modes").at(mode);
    EXPECT_GT(m.at("samples_per_s").get<double>(), 0.0) << mode;
    EXPECT_GT(m.at("live_samples_per_s").get<double>(), 0.0) << mode;
    EXPECT_TRUE(fs::exists(dir / (std::string("volume_") + mode + ".png"))) << mode;
  }
  EXPECT_GT(j.at("modes").at("isosurface").at("macrocells_skipped_fraction").get<double>(), 0.0);
  EXPECT_GT(j.at("modes").at("direct").at("volume_samples_per_s").get<double>(), 0.0);
  EXPECT_FALSE(fs::exists(dir / "phantom_128x128x128.raw"));  // removed unless --keep
}

TEST(VolumeCli, BadVolumesStopWithOneLine) {
  const auto dir = fresh_dir("volume_bad");
  std::ofstream(dir / "bad.nrrd") << "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n";
  std::ofstream(dir / "s.json") << R"({"materials":{"m":{"class":"diffuse"}},"objects":[{"type":"volume","file":"bad.nrrd","isovalue":1,"material":"m"}]})";
  std::ofstream(dir / "r.json") << R"({"materials":{"m":{"class":"diffuse"}},"objects":[{"type":"volume","file":"none.raw","dims":[4,4,4],"format":"uint8","isovalue":1,"material":"m"}]})";
  for (const std::string& scene : {std::string("volume:cube:8"), (dir / "s.json").string(), (dir / "r.json").string()}) {
    const auto out = dir / "out.exr";
    const CommandResult r = run_frameless("render " + scene + " --size 16x16 --out " + out.string());
    EXPECT_NE(r.exit_code, 0) << scene;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_FALSE(fs::exists(out)) << scene;
  }
}

}  // namespace
}  // namespace frameless
