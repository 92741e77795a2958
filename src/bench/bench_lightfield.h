// `frameless bench lightfield`: a light slab's accuracy, memory and cost against the model it was
// baked from. Its flags are in tools/bench_lightfield_command.cpp.
#pragma once
#include <string>
#include <vector>

namespace frameless::bench {

// The defaults are the command's.
struct LightfieldBenchOptions {
  std::string model = "/usr/share/glmark2/models/bunny.obj";
  // Slab resolutions "UVxUV:STxST".
  std::vector<std::string> resolutions{"8x8:64x64", "16x16:128x128", "16x16:256x256"};
  std::string size = "320x240";
  int spp = 4;        // per texel when baking and per pixel when rendering
  int repeats = 3;
  int threads = 0;    // baking (0: all cores); renders are timed on one thread
  bool json = false;
  std::string out;
};

int run_lightfield(const LightfieldBenchOptions& options);

}  // namespace frameless::bench
