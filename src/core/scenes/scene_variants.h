// Variants of a loaded scene for the ablation benchmark and the precision tests (loading thread).
#pragma once
#include <string>

#include "core/scene/scene.h"

namespace frameless {

// Ablation variants of a loaded scene (benchmarks and tests; re-finalizes the scene):
//   "no-lights"      removes every light (shading keeps the ambient term);
//   "no-dielectric"  turns dielectrics into polished spheres of the same highlight;
//   "no-highlights"  sets kh = 0 everywhere; a metal's highlight is its ks, so metals become
//                    polished coats with r0 = ks and no highlight.
// Returns false for an unknown name.
bool apply_scene_variant(Scene& scene, const std::string& variant);

// Moves the whole scene (geometry, lights, camera, ambient axis unchanged) by `offset`;
// re-finalizes. For precision tests far from the origin.
void translate_scene(Scene& scene, const Vec3& offset);

}  // namespace frameless
