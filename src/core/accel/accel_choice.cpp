// Which structure a scene gets (seed section 2: "for a given scene, we can empirically test both
// methods to arrive at the 'best' combination"): the BVH, the hybrid grid, or, for auto, both
// built and run on the same fixed trial rays, keeping the one that does less weighted work.
// Work is counted, not timed, so the choice does not depend on what else the machine is doing.
#include <chrono>
#include <cmath>

#include "core/accel/accel_impl.h"
#include "core/base/rng.h"
#include "core/geometry/geometry.h"  // geometry_bounds

namespace frameless {
namespace {

// Relative cost of one unit of work, fitted once (least squares) to `frameless bench accel` times
// on default, bunny and spheres:100000 (docs/accel.md): 23 ns per 8-wide BVH node (eight box tests
// and a sort), 8.6 ns per grid step (a cell, or a node of a cell's binary BVH), 16.5 ns per
// primitive test, in units of a primitive test.
constexpr double kBvhNodeCost = 1.4;
constexpr double kGridNodeCost = 0.52;
constexpr double kPrimCost = 1.0;

// Trial rays when the caller gave none: between random points of the scene's box (seeded).
std::vector<Ray> box_rays(const Geometry& g, int n) {
  Vec3 lo, hi;
  std::vector<Ray> rays;
  if (!geometry_bounds(g, lo, hi) || !is_finite(lo) || !is_finite(hi)) return rays;
  Rng rng(0xacce1);
  auto point = [&] { return lo + (hi - lo) * Vec3(rng.next_float(), rng.next_float(), rng.next_float()); };
  for (int i = 0; i < n; ++i) {
    Ray r;
    r.org = point();
    const Vec3 d = point() - r.org;
    if (!(glm::dot(d, d) > 0.0f)) continue;
    r.dir = glm::normalize(d);
    rays.push_back(r);
  }
  return rays;
}

double weighted(const TraversalCounts& c, double node_cost) {
  return node_cost * double(c.nodes) + kPrimCost * double(c.prims);
}

}  // namespace

const char* accel_kind_name(AccelKind k) {
  switch (k) {
    case AccelKind::kBvh: return "bvh";
    case AccelKind::kGrid: return "grid";
    case AccelKind::kAuto: return "auto";
  }
  return "unknown";
}

bool parse_accel_kind(const std::string& name, AccelKind& out) {
  if (name == "bvh") out = AccelKind::kBvh;
  else if (name == "grid") out = AccelKind::kGrid;
  else if (name == "auto") out = AccelKind::kAuto;
  else return false;
  return true;
}

void Accel::build(Geometry& geom, const AccelConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  Impl& im = *impl_;
  im.grid.reset();
  GridConfig gc;
  gc.density = config.grid_density;
  gc.bvh_threshold = config.grid_bvh_threshold;
  auto build_grid = [&] {
    im.grid = std::make_unique<GridAccel>();
    im.grid->build(geom, gc);
  };
  // Scenes with instances keep the BVH: the top level is a BVH over them (no grid of instances).
  if (config.kind == AccelKind::kBvh || !geom.instances.empty()) {
    build_bvh(geom, config);
    return;
  }
  if (config.kind == AccelKind::kGrid) {
    std::vector<Bvh8Node>().swap(im.nodes);
    std::vector<LeafTriangle>().swap(im.leaf_tris);  // the grid reads the vertices themselves
    std::vector<TriangleBlock>().swap(im.blocks);
    im.geom = &geom;
    build_grid();
    AccelStats& s = im.stats;
    const size_t geometry_bytes = s.geometry_bytes;  // set by an earlier BVH build, if any
    s = {};
    s.structure = AccelKind::kGrid;
    s.bytes = im.grid->stats().bytes;
    s.geometry_bytes = geometry_bytes;
    s.build_ms = im.grid->stats().build_ms;
    return;
  }
  // Auto: the BVH first (its build may reorder the primitives), then the grid over that order.
  build_bvh(geom, config);
  AccelStats bvh_stats = im.stats;
  build_grid();
  std::unique_ptr<GridAccel> grid = std::move(im.grid);  // trial the BVH alone first
  std::vector<Ray> rays = config.trial_rays;
  if (rays.empty()) rays = box_rays(geom, 4096);
  TraversalCounts bvh_c, grid_c;
  std::vector<Ray> shadow;  // from each camera-ray hit to each light
  for (const Ray& r : rays) {
    Hit h;
    if (!intersect_counted(r, h, bvh_c)) continue;
    const Vec3 p = r.org + h.t * r.dir;
    for (const Vec3& light : config.trial_lights) {
      const Vec3 d = light - p;
      const float len = glm::length(d);
      if (!(len > 0.0f) || !std::isfinite(len)) continue;
      Ray s;
      s.dir = d / len;
      s.org = p + s.dir * (1e-4f * len);  // the counts need no exact offset, only the same rays
      s.tmax = len * 0.999f;
      shadow.push_back(s);
    }
  }
  for (const Ray& r : shadow) occluded_counted(r, bvh_c);
  im.grid = std::move(grid);
  for (const Ray& r : rays) {
    Hit h;
    intersect_counted(r, h, grid_c);
  }
  for (const Ray& r : shadow) occluded_counted(r, grid_c);
  const double bvh_cost = weighted(bvh_c, kBvhNodeCost), grid_cost = weighted(grid_c, kGridNodeCost);
  const bool use_grid = grid_cost < bvh_cost;
  AccelStats s = bvh_stats;
  s.trial = true;
  s.trial_rays = rays.size() + shadow.size();
  s.bvh_build_ms = bvh_stats.build_ms;
  s.grid_build_ms = im.grid->stats().build_ms;
  s.bvh_bytes = bvh_stats.bytes;
  s.grid_bytes = im.grid->stats().bytes;
  s.bvh_cost = bvh_cost;
  s.grid_cost = grid_cost;
  s.bvh_counts = bvh_c;
  s.grid_counts = grid_c;
  if (use_grid) {
    std::vector<Bvh8Node>().swap(im.nodes);
    std::vector<LeafTriangle>().swap(im.leaf_tris);  // the grid reads the vertices themselves
    std::vector<TriangleBlock>().swap(im.blocks);
    s.structure = AccelKind::kGrid;
    s.bytes = s.grid_bytes;
    s.nodes = s.leaves = 0;
    s.depth = 0;
  } else {
    im.grid.reset();
    s.structure = AccelKind::kBvh;
  }
  s.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  im.stats = s;
}

}  // namespace frameless
