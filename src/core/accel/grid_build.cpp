// Build of the hybrid grid (grid_accel.h): resolution, CSR cell lists, and a binned-SAH binary BVH
// in every crowded cell.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/accel/grid_accel.h"

namespace frameless {
namespace {

constexpr uint32_t kLeafSize = 4;  // primitives per cell-BVH leaf at most
constexpr int kBins = 16;
constexpr int kSahDepth = 32;  // deeper: median splits, so the traversal stack stays bounded

struct Box {
  Vec3 lo{kInfinity}, hi{-kInfinity};
  void grow(const Box& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
  void grow(const Vec3& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  bool empty() const { return !(lo.x <= hi.x); }
};

float half_area(const Box& b) {
  if (b.empty()) return 0.0f;
  const Vec3 e = b.hi - b.lo;
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

// Bounds of primitive id; false for primitives that no ray can hit (non-finite, bad indices).
// A new primitive kind adds a case here and in intersect_primitive (grid_accel.cpp).
bool primitive_bounds(const Geometry& g, uint32_t id, Box& box) {
  const uint32_t nt = g.num_triangles(), fp = g.first_patch();
  if (id < nt) {
    const UVec3 t = g.triangles[id];
    const size_t np = g.positions.size();
    if (t.x >= np || t.y >= np || t.z >= np) return false;
    const Vec3 &a = g.positions[t.x], &b = g.positions[t.y], &c = g.positions[t.z];
    // Checked one by one: min and max would drop a NaN coordinate.
    if (!is_finite(a) || !is_finite(b) || !is_finite(c)) return false;
    box.lo = glm::min(a, glm::min(b, c));
    box.hi = glm::max(a, glm::max(b, c));
  } else if (id < fp) {
    const Sphere& s = g.spheres[id - nt];
    box.lo = s.center - Vec3(std::abs(s.radius));
    box.hi = s.center + Vec3(std::abs(s.radius));
  } else {
    const PatchSurface& p = g.patches[id - fp];
    box.lo = p.lo();
    box.hi = p.hi();
  }
  return is_finite(box.lo) && is_finite(box.hi);
}

struct BuildRef {
  Box box;  // the primitive's bounds clipped to its (padded) cell
  Vec3 center;
  uint32_t id;
};

// Binary BVH over refs[begin, end) in DFS order; leaf indices point at id_base + position.
void build_cell_bvh(std::vector<GridAccel::Node>& nodes, BuildRef* refs, uint32_t begin,
                    uint32_t end, uint32_t id_base, int depth) {
  const uint32_t self = uint32_t(nodes.size());
  nodes.push_back({});
  Box bounds, centers;
  for (uint32_t i = begin; i < end; ++i) bounds.grow(refs[i].box), centers.grow(refs[i].center);
  nodes[self].lo = bounds.lo;
  nodes[self].hi = bounds.hi;
  const uint32_t count = end - begin;
  if (count <= kLeafSize) {
    nodes[self].index = id_base + begin;
    nodes[self].count = count;
    return;
  }
  const Vec3 ext = centers.hi - centers.lo;
  const int axis = ext.x >= ext.y ? (ext.x >= ext.z ? 0 : 2) : (ext.y >= ext.z ? 1 : 2);
  uint32_t mid = begin + count / 2;
  if (!(ext[axis] > 0.0f)) {
    // All centres coincide: any halving is as good as another.
  } else if (depth >= kSahDepth) {
    std::nth_element(
        refs + begin, refs + mid, refs + end,
        [axis](const BuildRef& a, const BuildRef& b) { return a.center[axis] < b.center[axis]; });
  } else {
    // Binned SAH (Wald 2007) along the widest centre axis; centre min and max land in the first
    // and last bins, so both sides of every candidate plane are non-empty.
    const float scale = float(kBins) / ext[axis];
    auto bin_of = [&](const BuildRef& r) {
      return std::min(kBins - 1, int((r.center[axis] - centers.lo[axis]) * scale));
    };
    Box bin_box[kBins];
    uint32_t bin_count[kBins] = {};
    for (uint32_t i = begin; i < end; ++i) {
      const int b = bin_of(refs[i]);
      bin_box[b].grow(refs[i].box);
      ++bin_count[b];
    }
    float right_cost[kBins];
    Box acc;
    uint32_t n = 0;
    for (int b = kBins - 1; b > 0; --b) {
      acc.grow(bin_box[b]), n += bin_count[b];
      right_cost[b] = half_area(acc) * float(n);
    }
    acc = Box{}, n = 0;
    int best = 0;
    float best_cost = kInfinity;
    for (int b = 0; b < kBins - 1; ++b) {
      acc.grow(bin_box[b]), n += bin_count[b];
      const float cost = half_area(acc) * float(n) + right_cost[b + 1];
      if (cost < best_cost) best_cost = cost, best = b;
    }
    mid = uint32_t(std::partition(refs + begin, refs + end,
                                  [&](const BuildRef& r) { return bin_of(r) <= best; }) -
                   refs);
  }
  build_cell_bvh(nodes, refs, begin, mid, id_base, depth + 1);
  nodes[self].index = uint32_t(nodes.size());
  nodes[self].count = 0;
  build_cell_bvh(nodes, refs, mid, end, id_base, depth + 1);
}

// Cells per axis by the density rule over the axes that are not flat (a flat axis would get less
// than one cell: it gets exactly one and the others share the density), then clamped.
void choose_resolution(const Vec3& ext, size_t n, const GridConfig& cfg, int res[3]) {
  const double density = cfg.density > 0.0f ? double(cfg.density) : 2.0;
  // 32-bit cell indices: at most 2^30 cells.
  const int max_res = std::clamp(cfg.max_resolution, 1, 4096);
  const size_t max_cells = std::clamp<size_t>(cfg.max_cells, 1, size_t(1) << 30);
  bool flat[3] = {false, false, false};
  double k = 0.0;
  for (bool changed = true; changed;) {
    changed = false;
    double vol = 1.0;
    int dims = 0;
    for (int a = 0; a < 3; ++a)
      if (!flat[a]) vol *= double(ext[a]), ++dims;
    if (dims == 0) break;
    k = std::pow(density * double(n) / vol, 1.0 / dims);
    for (int a = 0; a < 3; ++a)
      if (!flat[a] && double(ext[a]) * k < 1.0) flat[a] = changed = true;
  }
  for (int a = 0; a < 3; ++a)
    res[a] = flat[a] ? 1 : int(std::clamp(double(ext[a]) * k, 1.0, double(max_res)));
  auto total = [&] { return size_t(res[0]) * size_t(res[1]) * size_t(res[2]); };
  if (total() > max_cells) {
    const double s = std::cbrt(double(max_cells) / double(total()));
    for (int a = 0; a < 3; ++a) res[a] = std::max(1, int(double(res[a]) * s));
  }
  while (total() > max_cells) *std::max_element(res, res + 3) -= 1;
}

}  // namespace

void GridAccel::build(const Geometry& geom, const GridConfig& config) {
  const auto start = std::chrono::steady_clock::now();
  *this = GridAccel{};
  geom_ = &geom;
  list_max_ = uint32_t(std::max(0, config.bvh_threshold));

  const uint32_t n = geom.num_primitives();
  std::vector<Box> boxes(n);
  std::vector<uint32_t> valid;
  valid.reserve(n);
  Box scene;
  for (uint32_t p = 0; p < n; ++p)
    if (primitive_bounds(geom, p, boxes[p])) valid.push_back(p), scene.grow(boxes[p]);

  if (!valid.empty()) {
    // Cells take every primitive whose bounds, grown by pad, overlap them: rounding in the DDA and
    // in a point's cell index stays far below pad, so a hit point is never in a cell that lacks
    // its primitive (for ray origins within ~30 scene radii of the scene).
    const float mag = max_component(glm::max(glm::abs(scene.lo), glm::abs(scene.hi)));
    pad_ = std::max(0x1p-17f * mag, 1e-30f);
    lo_ = scene.lo - Vec3(2.0f * pad_);
    hi_ = scene.hi + Vec3(2.0f * pad_);
    const Vec3 ext = hi_ - lo_;
    auto cell_range = [this](const Box& b, int c0[3], int c1[3]) {
      for (int a = 0; a < 3; ++a) {
        c0[a] = std::clamp(int((b.lo[a] - pad_ - lo_[a]) * inv_cell_[a]), 0, res_[a] - 1);
        c1[a] = std::clamp(int((b.hi[a] + pad_ - lo_[a]) * inv_cell_[a]), 0, res_[a] - 1);
      }
    };
    auto for_cells = [this](const int c0[3], const int c1[3], auto&& f) {
      for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
          for (int x = c0[0]; x <= c1[0]; ++x) f((size_t(z) * res_[1] + y) * res_[0] + x);
    };
    // Count references per cell (into offsets_[c + 1]). 32-bit offsets bound the total (huge
    // primitives in a fine grid): past that, coarsen and count again.
    GridConfig cfg = config;
    for (;;) {
      choose_resolution(ext, valid.size(), cfg, res_);
      for (int a = 0; a < 3; ++a) {
        cell_[a] = ext[a] / float(res_[a]);
        inv_cell_[a] = float(res_[a]) / ext[a];
      }
      offsets_.assign(size_t(res_[0]) * res_[1] * res_[2] + 1, 0);
      uint64_t refs = 0;
      for (uint32_t p : valid) {
        int c0[3], c1[3];
        cell_range(boxes[p], c0, c1);
        for_cells(c0, c1, [&](size_t c) { ++offsets_[c + 1]; });
        refs += uint64_t(c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1);
      }
      const size_t cells = offsets_.size() - 1;
      if (refs + cells < (uint64_t(1) << 31) || cells == 1) break;
      cfg.max_cells = std::max<size_t>(1, cells / 8);
    }
    const size_t cells = offsets_.size() - 1;
    // A crowded cell also stores its BVH root index, in front of its primitive ids.
    for (size_t c = 0; c < cells; ++c)
      if (offsets_[c + 1] > list_max_) ++offsets_[c + 1], ++stats_.cell_bvhs;
    for (size_t c = 0; c < cells; ++c) offsets_[c + 1] += offsets_[c];
    ids_.resize(offsets_[cells]);
    std::vector<uint32_t> cursor(offsets_.begin(), offsets_.end() - 1);
    for (size_t c = 0; c < cells; ++c) cursor[c] += offsets_[c + 1] - offsets_[c] > list_max_;
    for (uint32_t p : valid) {
      int c0[3], c1[3];
      cell_range(boxes[p], c0, c1);
      for_cells(c0, c1, [&](size_t c) { ids_[cursor[c]++] = p; });
    }
    cursor = {};
    occupied_.assign((cells + 63) / 64, 0);
    std::vector<BuildRef> refs;
    for (size_t c = 0; c < cells; ++c) {
      const uint32_t b = offsets_[c], e = offsets_[c + 1];
      stats_.refs += e - b;
      stats_.nonempty += e > b;
      occupied_[c / 64] |= uint64_t(e > b) << (c % 64);
      if (e - b <= list_max_) continue;
      --stats_.refs;  // the root slot
      const Vec3 xyz(float(c % res_[0]), float(c / res_[0] % res_[1]),
                     float(c / (size_t(res_[0]) * res_[1])));
      // Clipping to the (padded) cell tightens the boxes of primitives that span many cells.
      const Vec3 cell_lo = lo_ + xyz * cell_ - Vec3(pad_);
      const Vec3 cell_hi = lo_ + (xyz + 1.0f) * cell_ + Vec3(pad_);
      refs.clear();
      for (uint32_t i = b + 1; i < e; ++i) {
        BuildRef r;
        r.id = ids_[i];
        r.box.lo = glm::max(boxes[r.id].lo, cell_lo);
        r.box.hi = glm::min(boxes[r.id].hi, cell_hi);
        r.center = 0.5f * (r.box.lo + r.box.hi);
        refs.push_back(r);
      }
      ids_[b] = uint32_t(nodes_.size());
      build_cell_bvh(nodes_, refs.data(), 0, uint32_t(refs.size()), b + 1, 0);
      for (size_t i = 0; i < refs.size(); ++i) ids_[b + 1 + i] = refs[i].id;
    }
  }
  for (int a = 0; a < 3; ++a) stats_.res[a] = res_[a];
  stats_.cells = offsets_.empty() ? 0 : offsets_.size() - 1;
  stats_.bytes = offsets_.size() * sizeof(uint32_t) + occupied_.size() * sizeof(uint64_t) +
                 ids_.size() * sizeof(uint32_t) + nodes_.size() * sizeof(Node);
  stats_.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace frameless
