// Interactive camera manipulation (orbit, pan, zoom, fly) as pure functions; input thread.
#pragma once
#include "core/scene/camera.h"

namespace frameless {

// Tuning of the mouse and keyboard mappings; defaults feel right at 60-120 Hz input.
struct CameraControlConfig {
  float orbit_deg_per_pixel = 0.3f;  // left-drag: degrees of rotation per pixel of mouse motion
  float zoom_per_notch = 0.85f;      // wheel: distance to the look-at point scales by this per notch
  float min_distance = 1e-3f;        // zoom never brings the eye closer than this to the look point
  float max_pitch_deg = 89.0f;       // orbit stops this close to the poles so up never flips
  float fly_speed_fraction = 0.5f;   // fly speed in (distance to look point) per second
};

// Rotates the eye about the look-at point: dx yaws about the up vector, dy pitches about the
// camera's right vector (pixels of mouse motion, right/down positive).
Camera orbit_camera(const Camera& camera, float dx_pixels, float dy_pixels,
                    const CameraControlConfig& config = {});

// Translates eye and look-at point together in the image plane so the point under the cursor
// follows it (dx, dy in pixels; viewport_height in pixels).
Camera pan_camera(const Camera& camera, float dx_pixels, float dy_pixels, int viewport_height);

// Moves the eye towards (notches > 0) or away from the look-at point.
Camera zoom_camera(const Camera& camera, float notches, const CameraControlConfig& config = {});

// First-person motion: right/up/forward in [-1, 1] (W/S forward, A/D right, Q/E down/up),
// applied for dt seconds; eye and look-at point move together.
Camera fly_camera(const Camera& camera, float right, float up, float forward, float dt_seconds,
                  const CameraControlConfig& config = {});

}  // namespace frameless
