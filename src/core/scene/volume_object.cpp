// Placing a volume: transforms between world and grid index space, bounds, macrocells.
#include "core/scene/volume_object.h"

#include <algorithm>

#include "core/scene/scene_finalize.h"

namespace frameless {

const char* volume_mode_name(VolumeMode mode) {
  return mode == VolumeMode::kIsosurface ? "isosurface" : mode == VolumeMode::kDirect ? "direct" : "mip";
}

void place_volume(VolumeObject& v, const Affine& transform) {
  const Vec3 sp = v.grid->spacing;
  v.to_world.m = transform.m * glm::mat3(glm::vec3(sp.x, 0, 0), glm::vec3(0, sp.y, 0), glm::vec3(0, 0, sp.z));
  v.to_world.t = transform.t;
  v.to_index.m = glm::inverse(v.to_world.m);
  v.to_index.t = -(v.to_index.m * v.to_world.t);
  v.normal_to_world = glm::transpose(v.to_index.m);
  const Vec3 top(float(v.grid->nx - 1), float(v.grid->ny - 1), float(v.grid->nz - 1));
  v.lo = Vec3(kInfinity);
  v.hi = Vec3(-kInfinity);
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner((c & 1) ? top.x : 0.0f, (c & 2) ? top.y : 0.0f, (c & 4) ? top.z : 0.0f);
    const Vec3 w = v.to_world.point(corner);
    v.lo = glm::min(v.lo, w);
    v.hi = glm::max(v.hi, w);
  }
  v.scale = std::max(max_component(glm::abs(v.lo)), max_component(glm::abs(v.hi)));
  if (!v.cells) v.cells = std::make_shared<Macrocells>(build_macrocells(*v.grid, 8, default_build_executor()));
  if (v.tf) v.set_transfer(v.tf);
}

void VolumeObject::set_transfer(std::shared_ptr<const TransferFunction> f) {
  tf = std::move(f);
  cell_opacity = macrocell_opacity(*cells, *tf);
  step_opacity = tf->step_opacity(step);
}

}  // namespace frameless
