// Bricking a sparse volume: where each brick's voxels come from, then one brick per leaf region
// (with its 9th face from the neighbours) and one per constant value.
#include "core/volume/sparse_volume.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace frameless {
namespace {

int64_t floor8(int64_t v) { return v >= 0 ? v / 8 * 8 : -((-v + 7) / 8 * 8); }

std::string at_index(const Index3& o, int i, int j, int k) {
  std::string s = "(";  // appended: GCC 12 warns falsely about the "(" + string form
  s.append(std::to_string(int64_t(o[0]) + i)).append(", ").append(std::to_string(int64_t(o[1]) + j));
  return s.append(", ").append(std::to_string(int64_t(o[2]) + k)).append(")");
}

}  // namespace

Result<BrickedGrid> brick_sparse_volume(const SparseVolume& s, const std::string& what, uint64_t max_bytes) {
  if (!std::isfinite(s.background)) return Error{what + ": the background is not a finite number"};
  int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
  const auto cover = [&](const Index3& o, int side) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], int64_t(o[a]));
      hi[a] = std::max(hi[a], int64_t(o[a]) + side - 1);
    }
  };
  for (const SparseLeaf& l : s.leaves) {
    for (int i = 0; i < 512; ++i)
      if (!std::isfinite(l.v[size_t(i)]))
        return Error{what + ": voxel " + at_index(l.origin, i >> 6, (i >> 3) & 7, i & 7) +
                     " is not a finite number"};
    cover(l.origin, 8);
  }
  for (const SparseTile& t : s.tiles) {
    if (!std::isfinite(t.value))
      return Error{what + ": the tile at " + at_index(t.origin, 0, 0, 0) +
                   " is not a finite number"};
    if (t.value != s.background) cover(t.origin, t.side);
  }
  if (lo[0] > hi[0]) return Error{what + ": holds no voxels other than the background"};
  int64_t n[3];
  Index3 origin{};
  for (int a = 0; a < 3; ++a) {
    const int64_t first = floor8(lo[a] - 1), last = hi[a] + 1;
    n[a] = last - first + 1;
    origin[size_t(a)] = int(first);
    if (first < INT32_MIN || last > INT32_MAX) return Error{what + ": index bounds beyond 32 bits"};
  }
  if (n[0] > kMaxVolumeSide || n[1] > kMaxVolumeSide || n[2] > kMaxVolumeSide ||
      uint64_t(n[0]) * uint64_t(n[1]) > kMaxVoxels ||
      uint64_t(n[0]) * uint64_t(n[1]) * uint64_t(n[2]) > kMaxVoxels)
    return Error{what + ": bounds " + std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" +
                 std::to_string(n[2]) + " exceed the grid limits (each side 2^20, 2^34 voxels)"};

  auto pool = std::make_shared<BrickPool>();
  BrickPool& p = *pool;
  p.bx = int((n[0] - 1) / 8 + 1), p.by = int((n[1] - 1) / 8 + 1), p.bz = int((n[2] - 1) / 8 + 1);
  const size_t count = size_t(p.bx) * size_t(p.by) * size_t(p.bz);
  // The brick table alone (4 bytes a brick of the bounds) may pass the limit: refused before the
  // passes over it (a few tiles far apart span millions of bricks).
  if (uint64_t(count) * sizeof(uint32_t) > max_bytes)
    return Error{what + ": its bounds span " + std::to_string(count) + " bricks, whose table would take " +
                 std::to_string((uint64_t(count) * sizeof(uint32_t)) >> 20) + " MB, more than the limit of " +
                 std::to_string(max_bytes >> 20) + " MB"};
  const auto brick = [&](int64_t x, int64_t y, int64_t z) {
    return (size_t(z) * size_t(p.by) + size_t(y)) * size_t(p.bx) + size_t(x);
  };
  // Where each brick region's voxels come from: a leaf (>= 0), a tile (-2 - i) or the background
  // (-1).
  std::vector<int32_t> source(count, -1);
  for (size_t i = 0; i < s.tiles.size(); ++i) {
    const SparseTile& t = s.tiles[i];
    int64_t b0[3], b1[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      b0[a] = std::max<int64_t>(0, (int64_t(t.origin[size_t(a)]) - origin[size_t(a)]) / 8);
      b1[a] =
          std::min<int64_t>((a == 0   ? p.bx
                             : a == 1 ? p.by
                                      : p.bz) -
                                1,
                            (int64_t(t.origin[size_t(a)]) + t.side - 1 - origin[size_t(a)]) / 8);
      if (int64_t(t.origin[size_t(a)]) + t.side - 1 < origin[size_t(a)] || b0[a] > b1[a])
        inside = false;
    }
    if (!inside) continue;  // a tile of background value outside the bounds
    for (int64_t z = b0[2]; z <= b1[2]; ++z)
      for (int64_t y = b0[1]; y <= b1[1]; ++y)
        for (int64_t x = b0[0]; x <= b1[0]; ++x) source[brick(x, y, z)] = -2 - int32_t(i);
  }
  for (size_t i = 0; i < s.leaves.size(); ++i) {
    const Index3& o = s.leaves[i].origin;
    source[brick((o[0] - origin[0]) / 8, (o[1] - origin[1]) / 8, (o[2] - origin[2]) / 8)] =
        int32_t(i);
  }
  const auto constant = [&](int32_t src) {
    return src == -1 ? s.background : s.tiles[size_t(-2 - src)].value;
  };
  // Voxel (x, y, z) of the grid, clamped into it.
  const auto voxel = [&](int64_t x, int64_t y, int64_t z) {
    x = std::min(x, n[0] - 1), y = std::min(y, n[1] - 1), z = std::min(z, n[2] - 1);
    const int32_t src = source[brick(x >> 3, y >> 3, z >> 3)];
    return src >= 0 ? s.leaves[size_t(src)].v[size_t(((x & 7) << 6) | ((y & 7) << 3) | (z & 7))]
                    : constant(src);
  };

  // First which bricks are stored (one per leaf region, one per constant value), so that their
  // memory is known, and refused past the limit, before any is made: a few kilobytes of tiles
  // can describe gigabytes of bricks.
  p.table.resize(count);
  std::unordered_map<uint32_t, uint32_t> constant_brick;  // value bits -> stored brick
  std::vector<uint32_t> stored;                            // stored brick -> the brick it was made for
  for (int64_t bz = 0; bz < p.bz; ++bz)
    for (int64_t by = 0; by < p.by; ++by)
      for (int64_t bx = 0; bx < p.bx; ++bx) {
        // The regions that hold this brick's 9^3 voxels: itself and (clamped) its upper neighbours.
        bool uniform = true;
        const int32_t own = source[brick(bx, by, bz)];
        const float v0 = own >= 0 ? 0.0f : constant(own);
        for (int k = 0; k < 8 && uniform; ++k) {
          const int64_t x = std::min(bx * 8 + 8 * (k & 1), n[0] - 1) >> 3,
                        y = std::min(by * 8 + 4 * (k & 2), n[1] - 1) >> 3,
                        z = std::min(bz * 8 + 2 * (k & 4), n[2] - 1) >> 3;
          const int32_t src = source[brick(x, y, z)];
          uniform =
              src < 0 && constant(src) == v0 && std::signbit(constant(src)) == std::signbit(v0);
        }
        uint32_t bits = 0;
        std::memcpy(&bits, &v0, 4);
        if (uniform) {
          if (auto it = constant_brick.find(bits); it != constant_brick.end()) {
            p.table[brick(bx, by, bz)] = it->second;
            continue;
          }
        }
        const uint32_t id = uint32_t(stored.size());  // at most count: the grid limits keep it far below 2^32
        p.table[brick(bx, by, bz)] = id;
        if (uniform) constant_brick.emplace(bits, id);
        stored.push_back(uint32_t(brick(bx, by, bz)));
      }
  const uint64_t bytes = uint64_t(stored.size()) * kBrickVoxels * sizeof(float) + uint64_t(count) * sizeof(uint32_t);
  if (bytes > max_bytes)
    return Error{what + ": its " + std::to_string(stored.size()) + " bricks would take " +
                 std::to_string(bytes >> 20) + " MB with their table, more than the limit of " +
                 std::to_string(max_bytes >> 20) + " MB"};
  p.voxels.resize(stored.size() * kBrickVoxels);
  float vmin = kInfinity, vmax = -kInfinity;
  for (size_t id = 0; id < stored.size(); ++id) {
    const int64_t b = stored[id], bx = b % p.bx, by = b / p.bx % p.by, bz = b / p.bx / p.by;
    float* out = p.voxels.data() + id * kBrickVoxels;
    for (int k = 0; k < kBrickSide; ++k)
      for (int j = 0; j < kBrickSide; ++j)
        for (int i = 0; i < kBrickSide; ++i) {
          const float v = voxel(bx * 8 + i, by * 8 + j, bz * 8 + k);
          *out++ = v;
          vmin = std::min(vmin, v), vmax = std::max(vmax, v);
        }
  }

  auto g = std::make_shared<VolumeGrid>();
  g->nx = int(n[0]), g->ny = int(n[1]), g->nz = int(n[2]);
  g->type = VoxelType::kFloat32;
  g->bricks = std::move(pool);
  g->min_value = vmin;
  g->max_value = vmax;
  return BrickedGrid{std::move(g), origin};
}

}  // namespace frameless
