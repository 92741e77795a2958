// `frameless bench volume`: a Visible-Female-sized CT-like volume (the seed's data is not
// packaged: the Shepp-Logan head phantom at 512 x 512 x 1734 16-bit voxels) written as a raw
// file, loaded (memory-mapped) and given its macrocells, then rendered as an isosurface, through
// the volume shader and by MIP: load time, resident memory against the data, samples per second,
// what the macrocells skip, and the live frameless engine at 512 x 512. Flags:
// tools/bench_volume_command.cpp.
#pragma once
#include <string>

namespace frameless::bench {

struct VolumeOptions {
  std::string dims = "512x512x1734";
  std::string size = "512x512";
  int threads = 0;        // 0: all
  int spp = 1;
  double seconds = 3.0;   // each live engine run
  bool json = false;
  bool quick = false;     // a 128^3 phantom, 128 x 128, short runs
  std::string out;        // output directory (volume.json); the raw file goes there too
  bool keep = false;      // keep the raw file
};

int run_volume(const VolumeOptions& options);

}  // namespace frameless::bench
