// Baking the irradiance volume of ambient "irradiance_volume" (core/scene/irradiance_volume.h)
// with the path tracer: loading thread.
#pragma once
#include "core/scene/scene.h"

namespace frameless {

// Fills scene.ambient.volume: at each grid vertex, `samples` paths in uniformly distributed
// directions estimate the incident radiance (all light but Parker's lights' direct light, which
// the Whitted integrator adds itself), projected on order-2 harmonics and convolved with the
// cosine lobe. A vertex whose rays see back faces more than 40 % of the time lies inside
// geometry and is marked invalid. The scene must be finalized. Returns the seconds it took.
double bake_irradiance_volume(Scene& scene);

}  // namespace frameless
