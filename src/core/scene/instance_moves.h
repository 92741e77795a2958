// Where a scene's animated instances are at an instant (application side, one thread).
#pragma once
#include <vector>

#include "core/accel/instance_top.h"
#include "core/scene/scene.h"

namespace frameless {

// The moves that put the scene's animated instances (Scene::instance_motions) where their
// motions have them at time t (empty when none moves).
std::vector<InstanceMove> instance_moves_at(const Scene& scene, double t);

}  // namespace frameless
