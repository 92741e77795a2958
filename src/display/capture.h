// Headless capture of what a frameless display shows over time: engine + display thread + the
// window's GL draw code in an OSMesa context, each refresh read back and written as OpenEXR with a
// JSON manifest. Runs on the calling (capture) thread, which owns the GL context.
#pragma once
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/error.h"
#include "core/scene/scene.h"
#include "display/blend.h"
#include "display/camera_path.h"
#include "display/display_image.h"
#include "display/exr_io.h"
#include "frameless/engine_config.h"

namespace frameless {

class Engine;

// Float layers a capture can add next to the half RGB image.
inline constexpr const char* kCaptureLayers[] = {"age", "count", "variance", "epoch", "levels"};

struct CaptureOptions {
  std::string out_dir;             // frames, manifest and quick looks go here (created if missing)
  double duration = 2.0;           // seconds of (wall or virtual) time to capture
  double refresh_hz = 30.0;        // display refresh rate = capture frame rate
  EngineConfig engine;             // size, threads, mode, seed, deterministic, ...
  BlendConfig blend;               // decay alpha etc.
  Camera camera;                   // start camera (used when `path` is empty)
  CameraPath path;                 // camera over time; empty: still camera
  std::vector<std::string> layers; // subset of kCaptureLayers
  // False-colour views (ViewMode names but "shaded", e.g. "levels") drawn like the viewer's and
  // written per frame as NAME_NNNNN.png next to the EXR (listed in the manifest's frame records).
  std::vector<std::string> views;
  bool contact_sheet = true;       // contact_sheet.png after the frames
  bool mp4 = true;                 // sequence.mp4 when ffmpeg is installed
  bool progress = false;           // one updating line on stderr
  nlohmann::json settings = nlohmann::json::object();  // extra settings for the manifest (scene, CLI)
  // Called with the engine right after it started, and again (null) before it stops: a cluster
  // master connects its clients there (tools/cluster_join.h).
  std::function<void(Engine*)> engine_hook;
  // Set from a signal handler (SIGTERM, SIGINT): the capture stops at the next frame boundary,
  // so the manifest lists exactly the frames on disk.
  const std::atomic<bool>* cancel = nullptr;
};

// Test seam: called with each output file's final path before it is written; a returned message
// makes that write fail as if the disk were full.
struct CaptureHooks {
  std::function<std::optional<std::string>(const std::string& path)> before_write;
};

struct CaptureResult {
  int frames = 0;                  // frames written and listed in the manifest
  std::string manifest_path;
  std::string contact_sheet_path;  // empty when not written
  std::string mp4_path;            // empty when not written
  std::string note;                // e.g. why no MP4
  std::string gl_renderer;
};

// Checks (creating the folder if needed) that `dir` can be written, before any rendering starts.
Result<bool> prepare_output_dir(const std::string& dir);

// Writes a display image as EXR: half R, G, B from `rgb` (3 floats per pixel, row 0 at the top;
// null: the image's own rgb) plus the named float layers of kCaptureLayers (age in seconds,
// +inf where never updated; count; variance; epoch; levels). `attributes` are added as given.
Result<bool> write_display_exr(const std::string& path, const DisplayImage& image, const float* rgb,
                               const std::vector<std::string>& layers,
                               const ExrAttributes& attributes);

// "frame_00042.exr"
std::string capture_frame_name(int index);
// "levels_00042.png": a false-colour view's frame
std::string capture_view_name(const std::string& view, int index);

// Runs the capture. On a write failure mid-way the error says so, and every frame already written
// stays valid and is exactly what manifest.json lists.
Result<CaptureResult> run_capture(const Scene& scene, const CaptureOptions& options,
                                  const CaptureHooks& hooks = {});

}  // namespace frameless
