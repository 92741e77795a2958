// The two-level BVH's top level: an 8-wide BVH over the instances' world boxes; a ray entering
// an instance's box is transformed into its object space and traced through the shared mesh's
// own BVH (the bottom level, built once however many times the mesh is placed).
#include <algorithm>

#include "core/accel_impl.h"
#include "core/bvh_build.h"
#include "core/instance.h"

namespace frameless {

void Accel::build_instances(Geometry& geom, const AccelConfig& config) {
  Impl& im = *impl_;
  std::vector<Bvh8Node>().swap(im.tlas);
  const uint32_t n = uint32_t(geom.instances.size());
  if (n == 0) return;
  std::vector<PrimRef> refs(n);
  for (uint32_t i = 0; i < n; ++i) {
    const Instance& inst = geom.instances[i];
    refs[i].id = i;
    instance_bounds(inst, *geom.instance_meshes[inst.mesh], refs[i].lo, refs[i].hi);
    if (!is_finite(refs[i].lo) || !is_finite(refs[i].hi)) refs[i].lo = refs[i].hi = Vec3(0.0f);
  }
  Bvh8 bvh = build_bvh8(refs, n, config, n);
  // Instances in leaf order, as the flat primitives: a leaf is a run of consecutive instances.
  std::vector<Instance> ordered;
  ordered.reserve(n);
  for (const PrimRef& r : refs) ordered.push_back(geom.instances[r.id]);
  geom.instances.swap(ordered);
  im.tlas = std::move(bvh.nodes);
  im.stats.bytes += im.tlas.size() * sizeof(Bvh8Node);
  im.stats.geometry_bytes += geom.instances.size() * sizeof(Instance);
  // Each shared mesh counts once, however many instances place it.
  for (const std::shared_ptr<InstancedMesh>& m : geom.instance_meshes)
    im.stats.geometry_bytes += m->accel.stats().bytes + m->accel.stats().geometry_bytes;
}

namespace {

// Walks the top level; leaf(first, count) handles instances [first, first + count) and returns
// true to stop (any-hit). tmax() is the current interval end (shrinks as hits are found).
template <class Leaf, class Tmax>
bool walk_tlas(const std::vector<Bvh8Node>& tlas, const Ray& ray, Leaf&& leaf, Tmax&& tmax) {
  const BoxRay br = make_box_ray(ray);
  struct Entry {
    uint32_t ref, info;
    float t;
  } stack[kStackSize];
  int sp = 0;
  stack[sp++] = {0, 0, 0.0f};
  while (sp > 0) {
    const Entry e = stack[--sp];
    const float limit = tmax() * kRobustFar;
    if (e.t > limit) continue;
    if (e.info != 0) {
      if (leaf(e.ref, e.info & kLeafCountMask)) return true;
      continue;
    }
    const Bvh8Node& node = tlas[e.ref];
    alignas(32) float dist[kBvhWidth];
    uint32_t mask = intersect_children(node, br, ray.tmin, limit, dist);
    // Far children first onto the stack, so the nearest is walked first.
    Entry c[kBvhWidth];
    int m = 0;
    while (mask) {
      const int j = __builtin_ctz(mask);
      mask &= mask - 1;
      Entry x{node.child[j], node.info[j], dist[j]};
      int k = m++;
      while (k > 0 && c[k - 1].t < x.t) c[k] = c[k - 1], --k;
      c[k] = x;
    }
    for (int k = 0; k < m; ++k) stack[sp++] = c[k];
  }
  return false;
}

}  // namespace

bool Accel::intersect_instances(const Ray& ray, Hit& hit, bool found) const {
  const Impl& im = *impl_;
  const Geometry& g = *im.geom;
  float best = found ? hit.t : ray.tmax;
  walk_tlas(
      im.tlas, ray,
      [&](uint32_t first, uint32_t count) {
        for (uint32_t i = first; i < first + count; ++i) {
          const Instance& inst = g.instances[i];
          Ray r = to_object_ray(inst, ray);
          r.tmax = best;
          Hit h;
          if (!g.instance_meshes[inst.mesh]->accel.intersect(r, h)) continue;
          // Ties: flat geometry first, then the lower instance, then the lower primitive.
          const bool closer =
              !found || h.t < best ||
              (h.t == best && hit.inst != kInvalidId &&
               (i < hit.inst || (i == hit.inst && h.prim < hit.prim)));
          if (!closer) continue;
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

bool Accel::has_instances() const { return !impl_->tlas.empty(); }

bool Accel::occluded_instances(const Ray& ray) const {
  const Impl& im = *impl_;
  if (im.tlas.empty()) return false;
  const Geometry& g = *im.geom;
  return walk_tlas(
      im.tlas, ray,
      [&](uint32_t first, uint32_t count) {
        for (uint32_t i = first; i < first + count; ++i) {
          const Instance& inst = g.instances[i];
          if (g.instance_meshes[inst.mesh]->accel.occluded(to_object_ray(inst, ray))) return true;
        }
        return false;
      },
      [&] { return ray.tmax; });
}

}  // namespace frameless
