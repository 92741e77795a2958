// A reference closest-hit traversal of a sphere Bvh8 (accel.cpp's portable path) and brute force.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/accel/bvh_build.h"
#include "core/geometry/geometry.h"
#include "core/geometry/intersect_sphere.h"
#include "core/geometry/ray.h"

namespace frameless {
namespace test_util {

// The closest-hit traversal of accel.cpp (its portable path: same slab test, robust exit
// widening, near-to-far order, shrinking t), over any Bvh8 and sphere array.
inline constexpr float kRobustFar = 1.0f + 2.0f * (4.0f * 0x1p-24f) / (1.0f - 4.0f * 0x1p-24f);

inline bool traverse(const Bvh8& bvh, const std::vector<Sphere>& spheres, const Ray& ray,
                     Hit& hit) {
  if (bvh.nodes.empty()) return false;
  Vec3 inv, inv_far;
  int near[3];
  for (int a = 0; a < 3; ++a) {
    inv[a] = 1.0f / ray.dir[a];
    inv_far[a] = inv[a] * kRobustFar;
    near[a] = 2 * a + (std::signbit(ray.dir[a]) ? 1 : 0);
  }
  float tmax = ray.tmax, tmax_box = tmax * kRobustFar;
  bool found = false;
  struct Entry {
    uint32_t ref, info;
    float t;
  };
  std::vector<Entry> stack{{0, 0, 0.0f}};
  size_t visits = 0;  // a tree visits each node at most once per ray: more means a cycle
  while (!stack.empty()) {
    const Entry e = stack.back();
    stack.pop_back();
    if (e.t > tmax_box) continue;
    if (e.info == 0) {
      if (e.ref >= bvh.nodes.size() || ++visits > bvh.nodes.size()) {
        ADD_FAILURE() << "traversal left the tree (bad child index or a cycle)";
        return false;
      }
      const Bvh8Node& n = bvh.nodes[e.ref];
      Entry hits[kBvhWidth];
      int count = 0;
      for (int i = 0; i < kBvhWidth; ++i) {
        float tn = ray.tmin, tf = tmax_box;
        for (int a = 0; a < 3; ++a) {
          tn = std::max(tn, (n.bounds[near[a]][i] - ray.org[a]) * inv[a]);
          tf = std::min(tf, (n.bounds[near[a] ^ 1][i] - ray.org[a]) * inv_far[a]);
        }
        if (tn <= tf) hits[count++] = {n.child[i], n.info[i], tn};
      }
      for (int i = 1; i < count; ++i)  // far to near, so the nearest ends on top of the stack
        for (int j = i; j > 0 && hits[j - 1].t < hits[j].t; --j) std::swap(hits[j], hits[j - 1]);
      for (int i = 0; i < count; ++i) stack.push_back(hits[i]);
    } else {
      for (uint32_t k = 0; k < (e.info & kLeafCountMask); ++k) {
        float t;
        if (intersect_sphere(ray.org, ray.dir, spheres[e.ref + k], ray.tmin, tmax, t)) {
          tmax = t;
          tmax_box = t * kRobustFar;
          hit.t = t;
          hit.prim = e.ref + k;
          found = true;
        }
      }
    }
  }
  return found;
}

inline bool brute(const std::vector<Sphere>& spheres, const Ray& ray, Hit& hit) {
  float tmax = ray.tmax;
  bool found = false;
  for (uint32_t i = 0; i < spheres.size(); ++i) {
    float t;
    if (intersect_sphere(ray.org, ray.dir, spheres[i], ray.tmin, tmax, t))
      tmax = t, hit.t = t, hit.prim = i, found = true;
  }
  return found;
}

}  // namespace test_util
}  // namespace frameless
