// The JSON manifest of a capture: every setting once, then one record per written frame; written
// by the capture thread, read by tests and tools.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/error.h"
#include "core/scene/camera.h"

namespace frameless {

struct ManifestFrame {
  int index = 0;                 // frame number in the sequence (frame_00000.exr is 0)
  std::string file;              // file name relative to the manifest
  uint64_t display_tick = 0;     // display-thread tick that produced it (gaps: ticks not captured)
  double wall_time = -1;         // seconds since capture start; < 0 (written as null): virtual clock
  double virtual_time = 0;       // engine seconds at the tick
  Camera camera;                 // newest published camera at the tick
  uint32_t camera_epoch = 0;     // its epoch
  uint64_t samples = 0;          // samples rendered since the previous captured frame
  double coverage = 0;           // fraction of pixels whose newest sample used the newest camera
  std::string mode;              // "frameless" or "conventional"
  std::map<std::string, std::string> views;  // false-colour view name -> its PNG (capture --view)
};

struct Manifest {
  nlohmann::json settings = nlohmann::json::object();  // every setting, scene, seed, version
  std::vector<ManifestFrame> frames;
};

nlohmann::json manifest_to_json(const Manifest& manifest);
Result<Manifest> manifest_from_json(const nlohmann::json& j, const std::string& path);
// Written to a temporary name and renamed, so a reader sees the old or the new manifest, whole.
Result<bool> write_manifest(const std::string& path, const Manifest& manifest);
Result<Manifest> read_manifest(const std::string& path);

// Writes `text` to a temporary name next to `path` and renames it into place (any thread).
Result<bool> write_text_file_atomic(const std::string& path, const std::string& text);

}  // namespace frameless
