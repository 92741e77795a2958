// The viewer's controls: each edit a panel's widget makes, as a typed function (the panels call
// these) and by name with text values (the script's "set NAME VALUE..." calls the same
// functions). Main (window) thread.
#pragma once
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/volume/transfer_function.h"
#include "viewer/viewer_state.h"

namespace frameless {

// Scene-level settings: the session restarts (render threads stop, the scene changes, a new
// engine starts with the same camera and display settings).
void set_integrator(Viewer& v, Integrator integrator);
void set_shadows(Viewer& v, ShadowMode mode);
void set_accel(Viewer& v, AccelKind kind);
void set_closed_loop(Viewer& v, bool on);
// Lights, materials and moving objects: through the world channel (render threads never wait);
// a value the world refuses (core/scene/dynamic.h's world_problem) changes nothing.
Result<bool> set_light(Viewer& v, size_t index, const Light& light);
Result<bool> set_material(Viewer& v, size_t index, const MaterialParams& material);
Result<bool> set_object_position(Viewer& v, size_t index, const Vec3& position);
// Volumes (render threads stop while the scene changes).
void set_isovalue(Viewer& v, size_t volume, float isovalue);
Result<bool> set_transfer(Viewer& v, size_t volume, const std::vector<TransferPoint>& points);
Result<bool> set_transfer_preset(Viewer& v, size_t volume, const std::string& preset);

// "set NAME VALUE...": applies the control of that name (docs/viewer.md lists them); an error
// names the control and what is wrong with it, and changes nothing.
Result<bool> apply_control(Viewer& v, const std::string& name, const std::vector<std::string>& values);

}  // namespace frameless
