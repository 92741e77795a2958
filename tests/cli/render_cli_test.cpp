// The render command end to end: outputs, channels, and one-line errors with no file left behind.
#include <unistd.h>

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "cli_test_util.h"
#include "display/exr_io.h"

namespace frameless::test {
namespace {

TEST(RenderCli, WritesExrWithAllChannelsAndPng) {
  const auto dir = fresh_dir("render_ok");
  const auto exr = dir / "img.exr", png = dir / "img.png";
  const CommandResult r = run_frameless("render default --size 48x32 --spp 2 --threads 2 --out " +
                                        exr.string() + " --png " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(std::filesystem::exists(png));
  auto img = read_exr(exr.string());
  ASSERT_TRUE(img.ok()) << img.error().message;
  EXPECT_EQ(img->width, 48);
  EXPECT_EQ(img->height, 32);
  for (const char* c : {"R", "G", "B", "Z", "N.X", "N.Y", "N.Z", "samples"})
    EXPECT_EQ(img->channels.count(c), 1u) << c;
  EXPECT_EQ(img->half_channels.count("R"), 1u);  // colour is half, the rest float
  EXPECT_EQ(img->half_channels.count("Z"), 0u);
  // The default scene fills the view: finite depth somewhere, +inf nowhere inside the room,
  // unit normals where hit, exactly spp samples per pixel, no NaN anywhere.
  int hits = 0;
  for (size_t i = 0; i < img->channels["Z"].size(); ++i) {
    const float z = img->channels["Z"][i];
    EXPECT_FALSE(std::isnan(z));
    if (std::isfinite(z)) {
      ++hits;
      const float nx = img->channels["N.X"][i], ny = img->channels["N.Y"][i],
                  nz = img->channels["N.Z"][i];
      EXPECT_NEAR(nx * nx + ny * ny + nz * nz, 1.0f, 1e-3f);
    }
    EXPECT_EQ(img->channels["samples"][i], 2.0f);
    for (const char* c : {"R", "G", "B"}) EXPECT_TRUE(std::isfinite(img->channels[c][i]));
  }
  EXPECT_GT(hits, 48 * 32 / 2);
  // No temporary file is left next to the outputs.
  int files = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 2);
}

TEST(RenderCli, NoJitterIsDeterministicAcrossThreadCounts) {
  const auto dir = fresh_dir("render_det");
  const auto a = dir / "a.exr", b = dir / "b.exr";
  ASSERT_EQ(run_frameless("render default --size 24x16 --spp 3 --threads 1 --out " + a.string())
                .exit_code, 0);
  ASSERT_EQ(run_frameless("render default --size 24x16 --spp 3 --threads 2 --out " + b.string())
                .exit_code, 0);
  auto ia = read_exr(a.string()), ib = read_exr(b.string());
  ASSERT_TRUE(ia.ok() && ib.ok());
  EXPECT_EQ(ia->channels["R"], ib->channels["R"]);  // samples are pure functions of their inputs
  EXPECT_EQ(ia->channels["Z"], ib->channels["Z"]);
}

struct BadCase {
  const char* name;
  std::string args;
  const char* expect;  // substring the one-line error must contain
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class RenderBadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(RenderBadInput, OneLineErrorNonZeroExitNoOutput) {
  const auto dir = fresh_dir(std::string("render_bad_") + GetParam().name);
  const auto out = dir / "out.exr";
  std::string args = GetParam().args;
  if (const size_t at = args.find("--out DIR"); at != std::string::npos)  // a directory that must stay empty
    args.replace(at, 9, "--out " + (dir / "bench").string());
  if (args.find("--out") == std::string::npos) args += " --out " + out.string();
  const CommandResult r = run_frameless(args);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_LT(r.exit_code, 128) << "crashed: " << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find(GetParam().expect), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_TRUE(std::filesystem::is_empty(dir)) << "left a file behind";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RenderBadInput,
    ::testing::Values(
        BadCase{"size", "render default --size 0x10", "--size"},
        BadCase{"size_text", "render default --size big", "--size"},
        BadCase{"size_huge", "render default --size 99999x10", "--size"},
        BadCase{"missing_scene", "render /nonexistent/scene.json", "/nonexistent/scene.json"},
        BadCase{"unknown_builtin", "render nosuchscene", "nosuchscene"},
        BadCase{"camera", "render default --eye 0,0,0 --look 0,0,0", "camera"},
        BadCase{"fov", "render default --fov 180", "camera"},
        BadCase{"unwritable", "render default --out /proc/frameless_no/out.exr", "/proc"},
        BadCase{"out_not_exr", "render default --out DIR.png", "--out"},
        BadCase{"png_not_png", "render default --png /tmp/frameless_render_png_case.exr", "--png"},
        BadCase{"levels_not_png", "render default --levels-png /tmp/frameless_render_levels.jpg", "--levels-png"},
        BadCase{"integrator", "render cornell --integrator radiosity", "--integrator"},
        BadCase{"gi_spp", "bench gi --no-cycles --spp 0 --out DIR", "--spp"},
        BadCase{"gi_ref_spp", "bench gi --no-cycles --ref-spp 1 --out DIR", "--ref-spp"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace frameless::test
