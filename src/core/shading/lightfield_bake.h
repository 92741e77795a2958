// Baking a light slab (issue 28; `frameless bake-lightfield`, the built-in office): the scene seen
// from each node of the slab's uv plane through every texel of its st plane
// (core/scene/lightfield.h). Views are independent: the caller's executor may run them at once.
#pragma once
#include <functional>

#include "core/base/parallel_for.h"
#include "core/scene/lightfield.h"
#include "core/scene/scene.h"

namespace frameless {

struct LightfieldBakeOptions {
  uint32_t nu = 16, nv = 16;    // views on the uv plane
  uint32_t ns = 256, nt = 256;  // texels of each view on the st plane
  int spp = 4;                  // stratified samples per texel, across its st cell
  // Called after each view with the fraction done, from the thread that baked it (thread-safe).
  std::function<void(double)> progress;
};

// The slab that fits the scene's geometry and volumes (a cube around their bounding sphere) and
// faces its camera: z towards the eye, y along the camera's up. False when the scene is empty.
bool slab_around_scene(const Scene& scene, Affine& slab);

// Renders the slab's nu x nv views with the scene's integrator, one view per call of `pf`'s body
// (serial without one). Colour is premultiplied by the share of samples that hit something
// (alpha); misses add nothing (the background is not baked). Deterministic on any executor.
LightField bake_lightfield(const Scene& scene, const Affine& slab, const LightfieldBakeOptions& options,
                           const ParallelFor& pf = {});

// The camera of view (i, j): pixel (x, y) of an ns x nt image looks through the centre of st
// texel (x, nt - 1 - y).
CameraBasis lightfield_view(const Affine& slab, const LightField& lf, uint32_t i, uint32_t j);

}  // namespace frameless
