// Built-in scenes that need no files, and the animated state of Parker's bouncing balls;
// loading thread (pure functions).
#pragma once
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/geometry.h"
#include "core/scene.h"

namespace frameless {

// Where the bouncing balls are at time t seconds (t = 0 is the configuration that
// make_builtin_scene("balls") shows). Same count and order as the scene's spheres.
std::vector<Sphere> bouncing_balls_at(double t);

// Largest N that "spheres:N" accepts.
inline constexpr uint64_t kMaxRandomSpheres = 35'000'000;

// Path of the Stanford bunny shipped by Debian's glmark2-data.
// The textured showcase scene (builtin_showcase.cpp), not yet finalized.
Result<std::unique_ptr<Scene>> make_showcase();

inline constexpr const char* kBunnyPath = "/usr/share/glmark2/models/bunny.obj";

}  // namespace frameless
