// Packets through the two-level BVH's top level: the rays walk the instances' boxes together
// (each box tested per ray, one stack, each node fetched once for all of them), and at an
// instance each ray that reached it enters the mesh on its own. Walking the mesh as a packet
// too was slower on the sunflower field (primary packets 1.67-1.76 against 1.83-1.87 Mrays/s in
// three alternating rounds): a plant's thin parts split a packet at once. The answers are the single-ray walk's bit for bit: the same
// object-space rays, and a closest hit chosen by an order of (t, flat geometry first, instance,
// primitive) that does not depend on the visiting order.
#include <algorithm>

#include "core/accel/accel_impl.h"
#include "core/accel/instance.h"
#include "core/accel/instance_top.h"

namespace frameless {
namespace {

struct LaneEntry {
  uint32_t ref, info;
  float t;         // the nearest entry distance among its rays (ordering)
  uint32_t lanes;  // the rays that entered the box
};

// Walks the top level with the rays `lanes` of `rays`; leaf(first, count, lanes) handles
// instances [first, first + count) for the rays that entered the leaf's box and returns the rays
// still walking (an any-hit walk drops the blocked ones). tmax(i) is ray i's interval end.
template <class Leaf, class Tmax>
void walk_lanes(const std::vector<Bvh8Node>& nodes, const Ray* rays, int n, uint32_t lanes, Leaf&& leaf,
                Tmax&& tmax) {
  if (nodes.empty() || lanes == 0) return;
  BoxRay br[kPacketSize];
  for (int i = 0; i < n; ++i) br[i] = make_box_ray(rays[i]);
  LaneEntry stack[kStackSize];
  int sp = 0;
  uint32_t ref = 0, info = 0, at = lanes;  // the root, for every ray
  for (;;) {
    if (info != 0) {
      lanes = leaf(ref, info & kLeafCountMask, at);
      if (lanes == 0) return;
    } else {
      const Bvh8Node& node = nodes[ref];
      uint32_t entered[kBvhWidth] = {};
      float nearest[kBvhWidth];
      std::fill(nearest, nearest + kBvhWidth, kInfinity);
      uint32_t children = 0;
      for (uint32_t m = at; m; m &= m - 1) {
        const int i = __builtin_ctz(m);
        alignas(32) float dist[kBvhWidth];
        uint32_t mask = intersect_children(node, br[i], rays[i].tmin, tmax(i) * kRobustFar, dist);
        children |= mask;
        for (; mask; mask &= mask - 1) {
          const int j = __builtin_ctz(mask);
          entered[j] |= 1u << i;
          nearest[j] = std::min(nearest[j], dist[j]);
        }
      }
      if (children) {
        // Onto the stack far to near (by each child's nearest ray), then the nearest is walked.
        const int base = sp;
        for (; children; children &= children - 1) {
          const int j = __builtin_ctz(children);
          push_far_to_near(stack, base, sp, LaneEntry{node.child[j], node.info[j], nearest[j], entered[j]});
        }
        --sp;
        ref = stack[sp].ref, info = stack[sp].info, at = stack[sp].lanes & lanes;
        if (at) continue;
      }
    }
    // The nearest pending entry with a ray still walking.
    for (;;) {
      if (sp == 0) return;
      const LaneEntry& e = stack[--sp];
      if ((at = e.lanes & lanes) != 0) {
        ref = e.ref, info = e.info;
        break;
      }
    }
  }
}

// The rays `lanes` of `rays` in instance `inst`'s object space, packed: out[k] is ray lane[k].
// All of them before any walk: interleaving each transform with its ray's walk cost 7 % of the
// sunflower field's packet rays (1.57 against 1.69 Mrays/s, 6 of 6 rounds).
int object_rays(const Instance& inst, const Ray* rays, uint32_t lanes, Ray* out, int* lane) {
  int m = 0;
  for (; lanes; lanes &= lanes - 1, ++m) {
    lane[m] = __builtin_ctz(lanes);
    out[m] = to_object_ray(inst, rays[lane[m]]);
  }
  return m;
}

}  // namespace

void intersect_instances_packet(const InstanceTop& top, const Ray* rays, int n, Hit* hits) {
  n = std::clamp(n, 0, kPacketSize);
  float best[kPacketSize];
  for (int i = 0; i < n; ++i) best[i] = hits[i].valid() ? hits[i].t : rays[i].tmax;
  const MeshList& meshes = *top.meshes;
  walk_lanes(
      top.nodes, rays, n, (1u << n) - 1u,
      [&](uint32_t first, uint32_t count, uint32_t lanes) {
        for (uint32_t i = first; i < first + count; ++i) {
          const Instance& inst = top.instances[i];
          const Accel& mesh = meshes[inst.mesh]->accel;
          Ray obj[kPacketSize];
          int lane[kPacketSize];
          const int m = object_rays(inst, rays, lanes, obj, lane);
          Hit hs[kPacketSize];
          for (int k = 0; k < m; ++k) {
            obj[k].tmax = best[lane[k]];
            if (!mesh.intersect(obj[k], hs[k])) hs[k] = Hit{};
          }
          for (int k = 0; k < m; ++k) {
            if (!hs[k].valid()) continue;
            const int l = lane[k];
            const Hit& h = hs[k];
            Hit& hit = hits[l];
            if (!instance_hit_wins(h, i, hit, hit.valid(), best[l])) continue;
            hit = h;
            hit.inst = i;
            best[l] = h.t;
          }
        }
        return (1u << n) - 1u;
      },
      [&](int i) { return best[i]; });
}

void occluded_instances_packet(const InstanceTop& top, const Ray* rays, int n, bool* occluded) {
  n = std::clamp(n, 0, kPacketSize);
  uint32_t open = 0;  // the rays not yet blocked
  for (int i = 0; i < n; ++i) open |= uint32_t(!occluded[i]) << i;
  const MeshList& meshes = *top.meshes;
  walk_lanes(
      top.nodes, rays, n, open,
      [&](uint32_t first, uint32_t count, uint32_t lanes) {
        for (uint32_t i = first; i < first + count && (lanes &= open); ++i) {
          const Instance& inst = top.instances[i];
          const Accel& mesh = meshes[inst.mesh]->accel;
          Ray obj[kPacketSize];
          int lane[kPacketSize];
          const int m = object_rays(inst, rays, lanes, obj, lane);
          for (int k = 0; k < m; ++k)
            if (mesh.occluded(obj[k])) occluded[lane[k]] = true, open &= ~(1u << lane[k]);
        }
        return open;
      },
      [&](int i) { return rays[i].tmax; });
}

}  // namespace frameless
