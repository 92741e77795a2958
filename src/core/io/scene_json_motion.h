// JSON for objects that move (docs/scene-format.md, "Moving objects"): a sphere's "motion" and the
// scene's "physics" block; loading thread.
#pragma once
#include <string>
#include <vector>

#include "core/io/scene_json_util.h"
#include "core/scene/scene.h"

namespace frameless::scene_json {

// A sphere with "motion" (or "dynamic": true) becomes a dynamic object. Physics motions only
// record the ball; finish_physics() simulates them all together once every object is read.
struct PendingPhysics {
  std::vector<size_t> objects;  // indices into Scene::dynamic
  std::vector<BallState> balls;
};

void parse_dynamic_sphere(const json& o, const std::string& f, Scene& s, const Sphere& sphere,
                          uint16_t material, PendingPhysics& physics);
// An instance's "motion" (bounce or keyframes): declared instance `index` moves by it.
void parse_instance_motion(const json& motion, const std::string& f, Scene& s, uint32_t index);
void finish_physics(const json* physics, Scene& s, PendingPhysics& pending);

}  // namespace frameless::scene_json
