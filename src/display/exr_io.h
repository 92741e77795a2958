// OpenEXR output (and input, for tests and references) of float image planes; any thread.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/base/error.h"

namespace frameless {

// One channel: `data` points at the first pixel's value; consecutive pixels are `stride`
// floats apart (so RGB triples can be written as three strided channels without copies).
struct ExrChannel {
  std::string name;
  bool half = false;  // stored as 16-bit half in the file (data is still float in memory)
  const float* data = nullptr;
  size_t stride = 1;
};

struct ExrAttributes {
  std::map<std::string, std::string> strings;
  std::map<std::string, float> floats;
  std::map<std::string, double> doubles;
  std::map<std::string, int> ints;
  std::optional<double> frames_per_second;       // standard framesPerSecond (as a rational)
  std::optional<std::string> cap_date;           // standard capDate "YYYY:MM:DD HH:MM:SS"
  std::optional<std::vector<float>> world_to_camera;  // standard worldToCamera, 16 floats row-major
};

// Writes a scanline EXR (ZIP compression) to a temporary name and renames it into place.
Result<bool> write_exr(const std::string& path, int width, int height,
                       const std::vector<ExrChannel>& channels, const ExrAttributes& attributes = {});

struct ExrImage {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> channels;  // every channel read back as float
  std::map<std::string, std::string> half_channels;    // name -> "half" for channels stored as half
  ExrAttributes attributes;                            // the attribute kinds above that were present
};
Result<ExrImage> read_exr(const std::string& path);

}  // namespace frameless
