// The two-level BVH's top level: built over the instances' world boxes, refit when instances
// move, walked by rays that then enter each instance's shared bottom level in object space (the
// one intended recursion of the layers: that bottom level is an Accel too, see accel_instances.cpp).
#include "core/accel/instance_top.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/accel/accel_impl.h"
#include "core/accel/bvh_build.h"
#include "core/accel/instance.h"

namespace frameless {
namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double half_area(const Vec3& lo, const Vec3& hi) {
  const Vec3 d = hi - lo;
  return d.x >= 0.0f ? double(d.x) * d.y + double(d.y) * d.z + double(d.z) * d.x : 0.0;
}

// A non-finite box (an instance placed at infinity) becomes an empty point at the origin.
void checked_bounds(const Instance& inst, const MeshList& meshes, Vec3& lo, Vec3& hi) {
  instance_bounds(inst, *meshes[inst.mesh], lo, hi);
  if (!is_finite(lo) || !is_finite(hi)) lo = hi = Vec3(0.0f);
}

// Builds nodes over top.instances/lo/hi (in any order), then puts all four in leaf order.
void build_nodes(InstanceTop& top, const AccelConfig& config) {
  const uint32_t n = uint32_t(top.instances.size());
  std::vector<PrimRef> refs(n);
  for (uint32_t i = 0; i < n; ++i) refs[i].id = i, refs[i].lo = top.lo[i], refs[i].hi = top.hi[i];
  Bvh8 bvh = build_bvh8(refs, n, config, n);
  if (bvh.depth * (kBvhWidth - 1) + 1 > kStackSize) {
    std::fprintf(stderr, "frameless: accel: instance BVH depth %d exceeds the traversal stack\n", bvh.depth);
    std::abort();
  }
  std::vector<Instance> instances(n);
  std::vector<Vec3> lo(n), hi(n);
  std::vector<uint32_t> declared(n);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t i = refs[k].id;
    instances[k] = top.instances[i];
    lo[k] = top.lo[i], hi[k] = top.hi[i];
    declared[k] = top.declared[i];
  }
  top.instances.swap(instances);
  top.lo.swap(lo);
  top.hi.swap(hi);
  top.declared.swap(declared);
  top.position.assign(n, 0);
  for (uint32_t k = 0; k < n; ++k) top.position[top.declared[k]] = k;
  top.nodes = std::move(bvh.nodes);
}

// Recomputes node `ni`'s child boxes from its subtree (leaf boxes are the instances' boxes);
// returns the node's own box and adds the child box areas to `area`.
void refit_node(InstanceTop& top, uint32_t ni, Vec3& lo_out, Vec3& hi_out, double& area) {
  Bvh8Node& node = top.nodes[ni];
  lo_out = Vec3(kInfinity);
  hi_out = Vec3(-kInfinity);
  for (int j = 0; j < kBvhWidth; ++j) {
    if (node.bounds[0][j] > node.bounds[1][j]) continue;  // unused slot (empty box)
    Vec3 lo(kInfinity), hi(-kInfinity);
    if (node.info[j] == 0) {
      refit_node(top, node.child[j], lo, hi, area);
    } else {
      const uint32_t first = node.child[j], count = node.info[j] & kLeafCountMask;
      for (uint32_t k = first; k < first + count; ++k) lo = glm::min(lo, top.lo[k]), hi = glm::max(hi, top.hi[k]);
    }
    for (int a = 0; a < 3; ++a) node.bounds[2 * a][j] = lo[a], node.bounds[2 * a + 1][j] = hi[a];
    area += half_area(lo, hi);
    lo_out = glm::min(lo_out, lo);
    hi_out = glm::max(hi_out, hi);
  }
}

// Refits every node and returns the SAH cost: child box areas relative to the root's box.
double refit(InstanceTop& top) {
  if (top.nodes.empty()) return 0.0;
  Vec3 lo, hi;
  double area = 0.0;
  refit_node(top, 0, lo, hi, area);
  const double root = half_area(lo, hi);
  return root > 0.0 ? area / root : 0.0;
}

// Walks the top level; leaf(first, count) handles instances [first, first + count) and returns
// true to stop (any-hit). tmax() is the current interval end (shrinks as hits are found).
template <class Leaf, class Tmax>
bool walk(const std::vector<Bvh8Node>& nodes, const Ray& ray, Leaf&& leaf, Tmax&& tmax) {
  if (nodes.empty()) return false;
  const BoxRay br = make_box_ray(ray);
  struct Entry {
    uint32_t ref, info;
    float t;
  } stack[kStackSize];
  int sp = 0;
  uint32_t ref = 0, info = 0;  // the root
  for (;;) {
    if (info != 0) {
      if (leaf(ref, info & kLeafCountMask)) return true;
    } else {
      const Bvh8Node& node = nodes[ref];
      alignas(32) float dist[kBvhWidth];
      uint32_t mask = intersect_children(node, br, ray.tmin, tmax() * kRobustFar, dist);
      if (mask & (mask - 1)) {
        // Two or more: onto the stack far to near, and walked from the nearest.
        const int base = sp;
        for (; mask; mask &= mask - 1) {
          const int j = __builtin_ctz(mask);
          push_far_to_near(stack, base, sp, Entry{node.child[j], node.info[j], dist[j]});
        }
        --sp;
        ref = stack[sp].ref;
        info = stack[sp].info;
        continue;
      }
      if (mask) {  // one: descend without the stack
        const int j = __builtin_ctz(mask);
        ref = node.child[j];
        info = node.info[j];
        continue;
      }
    }
    // The nearest pending entry that may still hold a closer hit.
    for (;;) {
      if (sp == 0) return false;
      const Entry& e = stack[--sp];
      if (e.t <= tmax() * kRobustFar) {
        ref = e.ref;
        info = e.info;
        break;
      }
    }
  }
}

}  // namespace

size_t InstanceTop::bytes() const {
  return nodes.size() * sizeof(Bvh8Node) + instances.size() * sizeof(Instance) +
         (lo.size() + hi.size()) * sizeof(Vec3) + (declared.size() + position.size()) * sizeof(uint32_t);
}

std::shared_ptr<InstanceTop> build_instance_top(const std::vector<Instance>& instances,
                                                const MeshList& meshes, const AccelConfig& config) {
  auto top = std::make_shared<InstanceTop>();
  const uint32_t n = uint32_t(instances.size());
  top->meshes = &meshes;
  top->instances = instances;
  top->lo.resize(n);
  top->hi.resize(n);
  top->declared.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    checked_bounds(instances[i], meshes, top->lo[i], top->hi[i]);
    top->declared[i] = i;
  }
  build_nodes(*top, config);
  top->built_cost = top->cost = refit(*top);
  return top;
}

Result<std::shared_ptr<InstanceTop>> move_instances(const InstanceTop& from,
                                                    const std::vector<InstanceMove>& moves,
                                                    const AccelConfig& config, InstanceUpdate* info) {
  InstanceUpdate u;
  u.moved = moves.size();
  for (size_t k = 0; k < moves.size(); ++k)  // check everything before any work
    if (moves[k].index >= from.position.size())
      return Error{"move " + std::to_string(k) + ": instance " + std::to_string(moves[k].index) +
                   " out of range (the scene has " + std::to_string(from.position.size()) + ")"};
  auto t0 = std::chrono::steady_clock::now();
  auto top = std::make_shared<InstanceTop>(from);
  u.copy_ms = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  for (size_t k = 0; k < moves.size(); ++k) {
    const uint32_t p = top->position[moves[k].index];
    Instance& inst = top->instances[p];
    if (!make_instance(inst.mesh, moves[k].to_world, inst))
      return Error{"move " + std::to_string(k) + ": instance " + std::to_string(moves[k].index) +
                   ": singular or non-finite transform"};
    checked_bounds(inst, *top->meshes, top->lo[p], top->hi[p]);
  }
  top->cost = refit(*top);
  u.refit_ms = ms_since(t0);
  if (top->cost > kRebuildFactor * top->built_cost) {
    t0 = std::chrono::steady_clock::now();
    build_nodes(*top, config);
    top->built_cost = top->cost = refit(*top);
    u.rebuilt = true;
    u.rebuild_ms = ms_since(t0);
  }
  if (info) *info = u;
  return top;
}

bool intersect_instances(const InstanceTop& top, const Ray& ray, Hit& hit, bool found) {
  float best = found ? hit.t : ray.tmax;
  const MeshList& meshes = *top.meshes;
  walk(
      top.nodes, ray,
      [&](uint32_t first, uint32_t count) {
        for (uint32_t i = first; i < first + count; ++i) {
          const Instance& inst = top.instances[i];
          Ray r = to_object_ray(inst, ray);
          r.tmax = best;
          Hit h;
          if (!meshes[inst.mesh]->accel.intersect(r, h)) continue;
          if (!instance_hit_wins(h, i, hit, found, best)) continue;
          hit = h;
          hit.inst = i;
          best = h.t;
          found = true;
        }
        return false;
      },
      [&] { return best; });
  return found;
}

bool occluded_instances(const InstanceTop& top, const Ray& ray) {
  const MeshList& meshes = *top.meshes;
  return walk(
      top.nodes, ray,
      [&](uint32_t first, uint32_t count) {
        for (uint32_t i = first; i < first + count; ++i) {
          const Instance& inst = top.instances[i];
          if (meshes[inst.mesh]->accel.occluded(to_object_ray(inst, ray))) return true;
        }
        return false;
      },
      [&] { return ray.tmax; });
}

}  // namespace frameless
