// Plug-in shaders from the command line: the tutorial's shader, taken from docs/shaders.md, compiles
// against include/frameless/shader.h alone and renders with --shader-path; the example scene
// renders; a missing shader stops the command with one line and writes nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_test_util.h"

namespace frameless {
namespace {

namespace fs = std::filesystem;
using namespace frameless::test;

const fs::path kRoot = fs::path(FRAMELESS_TEST_DATA).parent_path().parent_path();

// The first ```c block of docs/shaders.md.
std::string tutorial_shader() {
  std::ifstream f(kRoot / "docs" / "shaders.md");
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string doc = ss.str();
  const size_t start = doc.find("```c\n"), end = doc.find("```", start + 5);
  return start == std::string::npos || end == std::string::npos ? "" : doc.substr(start + 5, end - start - 5);
}

TEST(ShaderCli, TheTutorialShaderCompilesAndRenders) {
  const auto dir = fresh_dir("shader_cli");
  const std::string source = tutorial_shader();
  ASSERT_NE(source.find("frameless_shader_v1"), std::string::npos) << "docs/shaders.md lost its shader";
  std::ofstream(dir / "stripes.c") << source;
  const std::string cc = "cc -O1 -shared -fPIC -I " + (kRoot / "include").string() + " " + (dir / "stripes.c").string() +
                         " -o " + (dir / "stripes.so").string() + " -lm 2>&1";
  ASSERT_EQ(std::system(cc.c_str()), 0) << cc;
  std::ofstream(dir / "s.json") << R"({"camera": {"eye": [0, 1, 4], "look": [0, 0, 0]},
    "lights": [{"type": "point", "position": [2, 4, 3]}],
    "materials": {"s": {"shader": "stripes", "params": {"b": [0.8, 0.2, 0.1], "width": 0.5}}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "s"}]})";
  // Found next to the scene, and by --shader-path.
  const CommandResult r = run_frameless("render " + (dir / "s.json").string() + " --size 48x32 --spp 1 --out " +
                                        (dir / "r.exr").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "r.exr"));
  const CommandResult e = run_frameless("render " + (kRoot / "docs" / "scenes" / "shaders.json").string() +
                                        " --size 48x32 --spp 1 --shader-path " + FRAMELESS_SHADER_DIR + " --out " +
                                        (dir / "e.exr").string());
  EXPECT_EQ(e.exit_code, 0) << e.output;
  // Both engine modes capture it (deterministic frames).
  for (const char* mode : {"frameless", "conventional"}) {
    const auto out = dir / (std::string("cap_") + mode);
    const CommandResult c = run_frameless("capture " + (dir / "s.json").string() + " --mode " + mode +
                                          " --deterministic --size 32x32 --refresh 10 --duration 0.2 "
                                          "--samples-per-tick 1024 --no-mp4 --no-contact-sheet --out " + out.string());
    EXPECT_EQ(c.exit_code, 0) << mode << ": " << c.output;
    EXPECT_TRUE(fs::exists(out / "frame_00001.exr")) << mode;
  }
}

TEST(ShaderCli, AMissingShaderIsOneLineAndNoOutput) {
  const auto dir = fresh_dir("shader_cli_missing");
  std::ofstream(dir / "s.json") << R"({"camera": {"eye": [0, 1, 4], "look": [0, 0, 0]},
    "materials": {"s": {"shader": "granite"}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "s"}]})";
  const CommandResult r = run_frameless("render " + (dir / "s.json").string() + " --size 16x16 --out " + (dir / "r.exr").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("materials.s.shader: shader 'granite': no granite.so"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "r.exr"));
}

}  // namespace
}  // namespace frameless
