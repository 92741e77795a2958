// The top level of the two-level BVH (OpenRT, Wald et al. 2003): an 8-wide BVH over instances'
// world boxes, immutable once built. Moving instances makes a new top from an old one (refit,
// or rebuilt when refits have loosened it too much) without touching the shared bottom levels;
// the application publishes the new top and render threads pick it up like the camera.
#pragma once
#include <memory>
#include <vector>

#include "core/accel/accel.h"
#include "core/accel/bvh_node.h"
#include "core/base/error.h"
#include "core/geometry/geometry.h"
#include "core/geometry/ray.h"

namespace frameless {

struct InstancedMesh;
using MeshList = std::vector<std::shared_ptr<InstancedMesh>>;

struct InstanceTop {
  std::vector<Bvh8Node> nodes;       // nodes[0] is the root
  std::vector<Instance> instances;   // leaf order: a leaf is a run of consecutive instances
  std::vector<Vec3> lo, hi;          // world box of each instance (leaf order)
  std::vector<uint32_t> declared;    // declared[k]: the Geometry::instances index of instances[k]
  std::vector<uint32_t> position;    // position[d]: where declared instance d sits in instances
  const MeshList* meshes = nullptr;  // the shared bottom levels (owned by the Geometry)
  double built_cost = 0.0;  // SAH cost (child box areas over the root's) when last built
  double cost = 0.0;        // the same now: refits of moved instances loosen boxes
  size_t bytes() const;
};

// Builds the top level over instances (declaration order) placing meshes.
std::shared_ptr<InstanceTop> build_instance_top(const std::vector<Instance>& instances,
                                                const MeshList& meshes,
                                                const AccelConfig& config = {});

// A new world transform for declared instance `index` (a differential update: only what moved).
struct InstanceMove {
  uint32_t index = 0;
  Affine to_world;
};

// What one update did and cost (bench instances reports it).
struct InstanceUpdate {
  size_t moved = 0;
  bool rebuilt = false;   // the refit cost passed kRebuildFactor times the built cost
  double copy_ms = 0.0;   // copying the old top (a published top is never written again)
  double refit_ms = 0.0;  // boxes of moved instances and every node's child boxes
  double rebuild_ms = 0.0;
};
inline constexpr double kRebuildFactor = 1.5;

// The top `from` with `moves` applied: copied, refit, rebuilt when needed. Error (naming the
// move) for an index out of range or a singular or non-finite transform; `from` never changes.
Result<std::shared_ptr<InstanceTop>> move_instances(const InstanceTop& from,
                                                    const std::vector<InstanceMove>& moves,
                                                    const AccelConfig& config = {},
                                                    InstanceUpdate* info = nullptr);

// Whether hit h on instance i (a position in the top) beats `hit`, the best so far at distance
// `best` (found: there is one): the nearer, and at an exact tie flat geometry first, then the lower
// instance, then the lower primitive. The order does not depend on the walk, so single rays and
// packets, which meet the instances in different orders, agree bit for bit.
inline bool instance_hit_wins(const Hit& h, uint32_t i, const Hit& hit, bool found, float best) {
  return !found || h.t < best ||
         (h.t == best && hit.inst != kInvalidId && (i < hit.inst || (i == hit.inst && h.prim < hit.prim)));
}

// Closest hit on the instances within hit (found: hit already holds a closer-or-equal candidate
// from flat geometry); hit.inst is the position in top.instances.
bool intersect_instances(const InstanceTop& top, const Ray& ray, Hit& hit, bool found);
// Any hit on the instances (shadow rays; early exit).
bool occluded_instances(const InstanceTop& top, const Ray& ray);

// The same for n <= kPacketSize rays walking the top level together, each entering the meshes on
// its own (instance_packet.cpp); the answers equal the single-ray ones bit for bit.
// hits[i] holds ray i's hit on flat geometry (invalid: none); occluded[i] true: already blocked.
void intersect_instances_packet(const InstanceTop& top, const Ray* rays, int n, Hit* hits);
void occluded_instances_packet(const InstanceTop& top, const Ray* rays, int n, bool* occluded);

}  // namespace frameless
