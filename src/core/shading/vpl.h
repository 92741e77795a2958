// Virtual point lights for instant global illumination (Keller 1997; Wald et al. 2002): light
// paths traced from the lights, a VPL where they touch a smooth surface. Pure, any thread.
#pragma once
#include <cstdint>
#include <vector>

#include "core/scene/dynamic.h"
#include "core/scene/scene.h"

namespace frameless {

// A VPL reflects `power` (the flux that arrived times the surface's albedo) diffusely from p
// into the hemisphere of n: a surface x sees it as f_x power / pi cos_x cos_y / d^2.
struct Vpl {
  Vec3 p{0.0f};
  Vec3 n{0.0f};
  Vec3 power{0.0f};
};

// Where light paths start from the directional lights and the environment: a sphere around
// everything (geometry_bounds).
struct SceneSphere {
  Vec3 center{0.0f};
  float radius = 1.0f;
};
SceneSphere scene_sphere(const Scene& scene);

// The VPLs of light-path set `set`: `paths` light paths, each from a light group chosen uniformly
// (the emissive triangles by power, each Parker light, the environment), started by the Halton
// sequence at indices set * paths + j; appended to out. An unbiased estimate of indirect light
// for every set: averaging over sets converges.
void generate_vpls(const Scene& scene, const DynamicFrame* frame, const SceneSphere& sphere,
                   uint64_t set, int paths, std::vector<Vpl>& out);

}  // namespace frameless
