// Instance motions evaluated at an instant, as moves for the instances' top level.
#include "core/scene/instance_moves.h"

namespace frameless {

std::vector<InstanceMove> instance_moves_at(const Scene& scene, double t) {
  std::vector<InstanceMove> moves;
  moves.reserve(scene.instance_motions.size());
  for (const InstanceMotion& m : scene.instance_motions) {
    Affine a = scene.geometry.instances.at(m.index).to_world;
    a.t += motion_offset(m.motion, t);
    moves.push_back({m.index, a});
  }
  return moves;
}

}  // namespace frameless
