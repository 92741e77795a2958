// `frameless bake-lightfield` end to end: it bakes a small model into a slab file that a scene
// places and renders (both engine modes capture it); bad flags and broken files stop the command
// with one line and write nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_test_util.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;
using namespace frameless::test;

TEST(LightfieldCli, BakesASlabThatAScenePlacesAndRenders) {
  const auto dir = fresh_dir("lightfield_cli");
  std::ofstream(dir / "model.json") << R"({"camera": {"eye": [0, 0, 5], "look": [0, 0, 0]},
    "lights": [{"type": "point", "position": [2, 4, 3]}],
    "materials": {"red": {"class": "diffuse", "kd": [0.8, 0.2, 0.1]}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "red"}]})";
  const CommandResult b = run_frameless("bake-lightfield " + (dir / "model.json").string() +
                                        " --uv 4x4 --st 24x24 --spp 1 --out " + (dir / "slab.exr").string() +
                                        " --png " + (dir / "slab.png").string());
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(b.output.find("4x4 views of 24x24 texels"), std::string::npos) << b.output;
  EXPECT_TRUE(fs::exists(dir / "slab.png"));
  std::ofstream(dir / "scene.json") << R"({"camera": {"eye": [0.5, 0.3, 6], "look": [0, 0, 0]},
    "materials": {"floor": {"class": "diffuse", "kd": 0.5}},
    "objects": [{"type": "plane", "point": [0, -1.5, 0], "normal": [0, 1, 0], "size": 10, "material": "floor"},
                {"type": "lightfield", "file": "slab.exr", "transform": {"translate": [0, 0, 0]}}]})";
  const CommandResult r = run_frameless("render " + (dir / "scene.json").string() + " --size 48x32 --spp 1 --out " +
                                        (dir / "r.exr").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* mode : {"frameless", "conventional"}) {
    const auto out = dir / (std::string("cap_") + mode);
    const CommandResult c = run_frameless("capture " + (dir / "scene.json").string() + " --mode " + mode +
                                          " --deterministic --size 32x32 --refresh 10 --duration 0.2 "
                                          "--samples-per-tick 1024 --no-mp4 --no-contact-sheet --out " + out.string());
    EXPECT_EQ(c.exit_code, 0) << mode << ": " << c.output;
    EXPECT_TRUE(fs::exists(out / "frame_00001.exr")) << mode;
  }
}

TEST(LightfieldCli, BadFlagsAndBrokenFilesAreOneLine) {
  const auto dir = fresh_dir("lightfield_cli_bad");
  const std::pair<std::string, std::string> cases[] = {
      {"bake-lightfield default --uv 0x4 --out " + (dir / "a.exr").string(), "--uv"},
      {"bake-lightfield default --st 9000x16 --out " + (dir / "a.exr").string(), "--st"},
      {"bake-lightfield default --spp 0 --out " + (dir / "a.exr").string(), "--spp"},
      {"bake-lightfield /nonexistent/model.obj --uv 2x2 --st 4x4 --out " + (dir / "a.exr").string(), "model.obj"},
  };
  for (const auto& [args, what] : cases) {
    const CommandResult r = run_frameless(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "a.exr"));
  std::ofstream(dir / "broken.exr") << "v/1\x01 not really";
  std::ofstream(dir / "scene.json") << R"({"objects": [{"type": "lightfield", "file": "broken.exr"}]})";
  const CommandResult r = run_frameless("render " + (dir / "scene.json").string() + " --out " + (dir / "r.exr").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("objects[0].file: "), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "r.exr"));
}

}  // namespace
}  // namespace frameless
