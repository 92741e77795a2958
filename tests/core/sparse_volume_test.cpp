// Bricked grids (sparse volumes, issue 27): every voxel reads back as the sparse volume defines it
// (leaves over tiles over the background), only the bricks that need it are stored, and
// isosurfaces, macrocells and the volume shader give bit-identical results on the bricked grid
// and on a dense copy of the same voxels.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "core/volume/isosurface.h"
#include "core/volume/sparse_volume.h"
#include "core/volume/transfer_function.h"
#include "core/volume/volume_march.h"

namespace frameless {
namespace {

// A ball of radius 13 around (5, -3, 9), as a narrow band of leaves (signed distance, clamped to
// +-3) with inside tiles of -3 and a far tile of 2, over the background 3.
SparseVolume ball() {
  SparseVolume s;
  s.background = 3.0f;
  s.tiles.push_back(SparseTile{{-128, -128, -128}, 128, -3.0f});  // covered by the leaves near the ball
  s.tiles.push_back(SparseTile{{64, 0, 0}, 8, 2.0f});
  const auto dist = [](int x, int y, int z) {
    const float d = std::sqrt(float((x - 5) * (x - 5) + (y + 3) * (y + 3) + (z - 9) * (z - 9))) - 13.0f;
    return std::clamp(d, -3.0f, 3.0f);
  };
  for (int lx = -16; lx <= 16; lx += 8)
    for (int ly = -24; ly <= 16; ly += 8)
      for (int lz = -8; lz <= 24; lz += 8) {
        SparseLeaf l;
        l.origin = {lx, ly, lz};
        bool band = false;
        for (int i = 0; i < 512; ++i) {
          l.v[size_t(i)] = dist(lx + (i >> 6), ly + ((i >> 3) & 7), lz + (i & 7));
          band |= std::abs(l.v[size_t(i)]) < 3.0f;
        }
        if (band) s.leaves.push_back(l);
      }
  return s;
}

// What the sparse volume says voxel (x, y, z) of index space holds.
float expected(const SparseVolume& s, int x, int y, int z) {
  for (const SparseLeaf& l : s.leaves)
    if (x >= l.origin[0] && x < l.origin[0] + 8 && y >= l.origin[1] && y < l.origin[1] + 8 && z >= l.origin[2] &&
        z < l.origin[2] + 8)
      return l.v[size_t(((x - l.origin[0]) << 6) | ((y - l.origin[1]) << 3) | (z - l.origin[2]))];
  float v = s.background;
  for (const SparseTile& t : s.tiles)
    if (x >= t.origin[0] && x < t.origin[0] + t.side && y >= t.origin[1] && y < t.origin[1] + t.side &&
        z >= t.origin[2] && z < t.origin[2] + t.side)
      v = t.value;
  return v;
}

std::shared_ptr<const VolumeGrid> dense_copy(const VolumeGrid& g) {
  std::vector<uint8_t> bytes(g.voxels() * 4);
  float* out = reinterpret_cast<float*>(bytes.data());
  for (int z = 0; z < g.nz; ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x) *out++ = g.at(x, y, z);
  return *make_volume_grid(g.nx, g.ny, g.nz, VoxelType::kFloat32, Vec3(1.0f), owned_storage(std::move(bytes)), "dense");
}

TEST(SparseVolume, VoxelsReadBackAndOnlyNeededBricksAreStored) {
  const SparseVolume s = ball();
  auto b = brick_sparse_volume(s, "ball");
  ASSERT_TRUE(b) << b.error().message;
  const VolumeGrid& g = *b->grid;
  ASSERT_TRUE(g.bricks);
  // The bounds: leaves and non-background tiles, one voxel more each way, the origin on 8.
  EXPECT_EQ(b->origin, (Index3{-136, -136, -136}));
  EXPECT_EQ(g.nx, 72 + 136 + 1);
  for (int a = 0; a < 3; ++a) EXPECT_EQ(b->origin[size_t(a)] % 8, 0);
  size_t checked = 0;
  for (int z = 0; z < g.nz; z += 3)
    for (int y = 0; y < g.ny; y += 2)
      for (int x = 0; x < g.nx; ++x, ++checked)
        ASSERT_EQ(g.at(x, y, z), expected(s, x + b->origin[0], y + b->origin[1], z + b->origin[2]))
            << "at grid voxel " << x << ", " << y << ", " << z;
  EXPECT_GT(checked, 800000u);
  EXPECT_EQ(g.min_value, -3.0f);
  EXPECT_EQ(g.max_value, 3.0f);
  // Stored: bricks touching a leaf or a tile's edge, and one per constant value.
  const BrickPool& p = *g.bricks;
  EXPECT_EQ(p.table.size(), size_t(p.bx) * p.by * p.bz);
  EXPECT_LT(p.stored(), p.table.size() / 4) << "the empty space must not be stored";
  EXPECT_GE(p.stored(), s.leaves.size());
}

TEST(SparseVolume, BrickedGridRendersBitIdenticallyToItsDenseCopy) {
  auto b = brick_sparse_volume(ball(), "ball");
  ASSERT_TRUE(b);
  const VolumeGrid& sparse = *b->grid;
  const auto dense = dense_copy(sparse);
  const Macrocells ms = build_macrocells(sparse), md = build_macrocells(*dense);
  ASSERT_EQ(ms.lo, md.lo);
  ASSERT_EQ(ms.hi, md.hi);
  auto tf = TransferFunction::make({{-3.0f, Vec3(0.1f, 0.2f, 0.9f), 0.3f}, {0.0f, Vec3(1.0f), 0.05f}, {3.0f, Vec3(0.0f), 0.0f}}, "tf");
  ASSERT_TRUE(tf);
  const std::vector<float> os = macrocell_opacity(ms, *tf), od = macrocell_opacity(md, *tf);
  const MarchSetup s_sparse{&sparse, &ms, &os, &*tf, 0.5f, nullptr}, s_dense{dense.get(), &md, &od, &*tf, 0.5f, nullptr};
  std::mt19937 rng(27);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const Vec3 centre(5.0f - float(b->origin[0]), -3.0f - float(b->origin[1]), 9.0f - float(b->origin[2]));
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 org = centre + Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 90.0f;
    const Vec3 dir = glm::normalize(centre + Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 30.0f - org);
    for (float iso : {0.0f, -1.5f, 2.5f}) {
      float ta = -1.0f, tb = -1.0f;
      const bool ha = intersect_isosurface(sparse, &ms, iso, org, dir, 0.0f, 1e30f, ta);
      const bool hb = intersect_isosurface(*dense, &md, iso, org, dir, 0.0f, 1e30f, tb);
      ASSERT_EQ(ha, hb) << "ray " << i << " iso " << iso;
      if (ha) ASSERT_EQ(ta, tb);
      hits += ha;
    }
    const VolumeSegment va = march_volume(s_sparse, org, dir, 0.0f, 200.0f, nullptr);
    const VolumeSegment vb = march_volume(s_dense, org, dir, 0.0f, 200.0f, nullptr);
    ASSERT_EQ(va.transmittance, vb.transmittance);
    ASSERT_EQ(va.color, vb.color);
    ASSERT_EQ(va.samples, vb.samples);
  }
  EXPECT_GT(hits, 2000);
}

TEST(SparseVolume, BadVolumesAreRefused) {
  SparseVolume empty;
  empty.background = 1.0f;
  empty.tiles.push_back(SparseTile{{0, 0, 0}, 8, 1.0f});  // the background's own value
  auto e = brick_sparse_volume(empty, "empty.vdb");
  ASSERT_FALSE(e);
  EXPECT_EQ(e.error().message, "empty.vdb: holds no voxels other than the background");

  SparseVolume nan = ball();
  nan.leaves[3].v[100] = std::nanf("");
  auto n = brick_sparse_volume(nan, "nan.vdb");
  ASSERT_FALSE(n);
  EXPECT_NE(n.error().message.find("nan.vdb: voxel ("), std::string::npos) << n.error().message;
  EXPECT_NE(n.error().message.find("is not a finite number"), std::string::npos);

  // A few tiles can ask for far more bricks than the file holds: past the limit, one line.
  SparseVolume tiles;
  tiles.tiles.push_back(SparseTile{{0, 0, 0}, 64, 1.0f});
  tiles.tiles.push_back(SparseTile{{64, 0, 0}, 64, 2.0f});
  auto fits = brick_sparse_volume(tiles, "tiles.vdb");
  ASSERT_TRUE(fits) << fits.error().message;
  const BrickPool& pool = *fits->grid->bricks;
  const uint64_t table = uint64_t(pool.bx) * uint64_t(pool.by) * uint64_t(pool.bz) * 4;
  const uint64_t bricks = pool.stored(), bytes = bricks * kBrickVoxels * 4 + table;
  auto over = brick_sparse_volume(tiles, "tiles.vdb", bytes - 1);
  ASSERT_FALSE(over);
  EXPECT_EQ(over.error().message, "tiles.vdb: its " + std::to_string(bricks) + " bricks would take " +
                                      std::to_string(bytes >> 20) + " MB with their table, more than the limit of " +
                                      std::to_string((bytes - 1) >> 20) + " MB");
  EXPECT_TRUE(brick_sparse_volume(tiles, "tiles.vdb", bytes));  // exactly fits
  // Tiles far apart: the table alone passes the limit, refused before any pass over it.
  SparseVolume apart;
  apart.tiles.push_back(SparseTile{{0, 0, 0}, 8, 1.0f});
  apart.tiles.push_back(SparseTile{{2000, 2000, 2000}, 8, 1.0f});  // bounds 2017^3: 253^3 bricks
  auto wide = brick_sparse_volume(apart, "apart.vdb", uint64_t(1) << 24);
  ASSERT_FALSE(wide);
  EXPECT_EQ(wide.error().message, "apart.vdb: its bounds span 16194277 bricks, whose table would take 61 MB, "
                                  "more than the limit of 16 MB");

  SparseVolume far = ball();
  far.tiles.push_back(SparseTile{{4096 * 300, 0, 0}, 4096, 1.0f});  // bounds wider than 2^20 voxels
  auto f = brick_sparse_volume(far, "far.vdb");
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().message.find("exceed the grid limits"), std::string::npos) << f.error().message;
}

}  // namespace
}  // namespace frameless
