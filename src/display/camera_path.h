// Camera paths for captures: keyframes (from a file, a viewer recording or command-line
// shorthands) and their smooth interpolation; any thread (pure data and functions).
#pragma once
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/scene/camera.h"

namespace frameless {

struct CameraKeyframe {
  double time = 0.0;  // seconds from the start of the capture
  Camera camera;
  bool cut = false;   // the camera jumps here: no interpolation from the previous keyframe
};

// Keyframes sorted by time. Between keyframes: Catmull-Rom (non-uniform, time-parameterised)
// on the eye position, slerp on the view orientation, linear on look distance and fov.
// Before the first / after the last keyframe the path holds still.
struct CameraPath {
  std::vector<CameraKeyframe> keyframes;
  double duration() const { return keyframes.empty() ? 0.0 : keyframes.back().time; }
};

// The camera at time t. An empty path returns `fallback`.
Camera evaluate_camera_path(const CameraPath& path, double t, const Camera& fallback = {});

// Command-line shorthands, composed: orbit by orbit_deg about the look-at point's up axis and
// dolly (eye distance multiplied by dolly_factor) over `duration`; with cut_at >= 0 the camera
// jumps at that time to the view orbited by a further cut_orbit_deg, and goes on from there.
struct PathShorthand {
  double orbit_deg = 0.0;
  double dolly_factor = 1.0;
  double cut_at = -1.0;
  double cut_orbit_deg = 90.0;
};
CameraPath make_shorthand_path(const Camera& start, const PathShorthand& shorthand,
                               double duration);

// JSON path file: {"keyframes": [{"t": 0.0, "eye": [x,y,z], "look": [x,y,z], "up": [x,y,z],
// "fov": 45, "cut": false}, ...]} ("up", "fov" and "cut" optional). The viewer's --record writes
// this format. Errors name the file and the field ("path.json: keyframes[3].eye: ...").
Result<CameraPath> load_camera_path(const std::string& path);
Result<CameraPath> parse_camera_path(const std::string& text, const std::string& path);
std::string camera_path_to_json(const CameraPath& path, const std::string& source);

// Camera as a 4x4 world-to-camera matrix, row-major, camera looking down -z with y up
// (the OpenEXR worldToCamera convention, applied to row vectors: p_cam = p_world * M).
std::vector<float> world_to_camera_matrix(const Camera& camera);

}  // namespace frameless
