// Textures of hits on instances: looked up in the shared mesh's object space (render threads).
#pragma once
#include "core/accel/instance_top.h"
#include "core/geometry/surface.h"
#include "core/scene/scene.h"

namespace frameless {

// Textures of a hit on an instance: evaluated in object space, the perturbed shading normal
// carried to world space into sp.
void apply_instance_textures(const Scene& scene, const InstanceTop& top, const Ray& ray,
                             const Hit& hit, MaterialParams& m, SurfacePoint& sp);

}  // namespace frameless
