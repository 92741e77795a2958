// libFuzzer target for the scene and mesh parsers: the first byte picks the parser
// (0: JSON scene, 1: OBJ, 2: PLY), the rest is its input. Build with -DFRAMELESS_FUZZ=ON and clang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string input(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (data[0] % 3) {
    case 0: {
      // A base directory with no meshes: "mesh" objects exercise the missing-file path.
      auto scene = frameless::parse_scene_json(input, "fuzz.json", "/nonexistent");
      (void)scene;
      break;
    }
    case 1: (void)frameless::parse_obj(input, "fuzz.obj"); break;
    case 2: (void)frameless::parse_ply(input, "fuzz.ply"); break;
  }
  return 0;
}
