// Light that bounces end to end: deterministic captures of the Cornell box under path tracing
// and igi are bit-identical run to run (with and without the denoiser), and every integrator
// renders the built-in scenes it is documented for.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "cli_test_util.h"

namespace frameless::test {
namespace {

std::string read_all(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// The frames of a capture directory, in name order.
std::vector<std::filesystem::path> frames(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".exr") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(GiCli, DeterministicCapturesAreBitIdentical) {
  const auto dir = fresh_dir("gi_det");
  for (const char* integrator : {"path", "igi"})
    for (const char* extra : {"", " --denoise"}) {
      std::vector<std::filesystem::path> runs;
      for (int k = 0; k < 2; ++k) {
        const auto out = dir / (std::string(integrator) + (*extra ? "_dn" : "") + std::to_string(k));
        const CommandResult r = run_frameless(
            std::string("capture cornell --integrator ") + integrator + extra +
            " --deterministic --size 48x48 --refresh 10 --duration 0.3 --samples-per-tick 4000"
            " --orbit 10 --no-mp4 --no-contact-sheet --threads 2 --out " + out.string());
        ASSERT_EQ(r.exit_code, 0) << r.output;
        runs.push_back(out);
      }
      const auto a = frames(runs[0]), b = frames(runs[1]);
      ASSERT_EQ(a.size(), 3u) << integrator << extra;
      ASSERT_EQ(a.size(), b.size());
      for (size_t i = 0; i < a.size(); ++i)
        EXPECT_EQ(read_all(a[i]), read_all(b[i])) << integrator << extra << " frame " << i;
    }
}

TEST(GiCli, EveryIntegratorRendersTheDocumentedScenes) {
  const auto dir = fresh_dir("gi_render");
  for (const char* scene : {"cornell", "room", "showcase", "default"})
    for (const char* integrator : {"whitted", "path", "igi"}) {
      const auto out = dir / (std::string(scene) + "_" + integrator + ".exr");
      const CommandResult r = run_frameless(std::string("render ") + scene + " --integrator " + integrator +
                                            " --size 40x30 --spp 2 --out " + out.string());
      EXPECT_EQ(r.exit_code, 0) << scene << " " << integrator << ": " << r.output;
      EXPECT_TRUE(std::filesystem::exists(out)) << scene << " " << integrator;
      EXPECT_NE(r.output.find("0 dropped"), std::string::npos) << r.output;  // no NaN/Inf sample
    }
}

}  // namespace
}  // namespace frameless::test
