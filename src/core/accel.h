// Bounding volume hierarchy over a Geometry: build once, then closest-hit and any-hit queries
// from any number of threads (const, no shared mutable state). Owns no threads.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>

#include "core/geometry.h"
#include "core/ray.h"

namespace frameless {

struct AccelConfig {
  int max_leaf_size = 4;  // primitives per leaf at most
  int sah_bins = 16;      // bins per axis for the binned SAH sweep
  // Optional executor for a parallel build: runs body(i) for every i in [0, n), possibly
  // concurrently, and returns when all are done (the caller owns the threads). Empty: serial.
  std::function<void(size_t n, const std::function<void(size_t)>& body)> parallel_for;
};

struct AccelStats {
  double build_ms = 0.0;
  size_t bytes = 0;  // BVH nodes plus any per-primitive data the accel keeps
  size_t nodes = 0;
  size_t leaves = 0;
  int depth = 0;  // node levels, root = 1
  // Geometry arrays the rays read: positions, triangle indices, spheres and material ids (not
  // shading normals). The memory budget applies to bytes + geometry_bytes.
  size_t geometry_bytes = 0;
};

class Accel {
 public:
  Accel();
  ~Accel();
  Accel(Accel&&) noexcept;
  Accel& operator=(Accel&&) noexcept;

  // Builds over geom; may permute geom's primitive arrays. geom must outlive the Accel.
  void build(Geometry& geom, const AccelConfig& config = {});

  // Closest hit in [ray.tmin, ray.tmax]; fills hit and returns true when found.
  bool intersect(const Ray& ray, Hit& hit) const;
  // Any hit in [ray.tmin, ray.tmax] (early exit): for shadow rays.
  bool occluded(const Ray& ray) const;

  const AccelStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace frameless
