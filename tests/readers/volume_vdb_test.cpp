// OpenVDB files (issue 27) written by OpenVDB 10 itself (tests/data/volumes/make_vdb_fixtures.cpp):
// every compression and half floats give the level set OpenVDB made, the fog volume's voxels, tiles
// and inactive values come back exactly, maps and grid choice work, and broken files (truncated,
// corrupted, or asking for what is not there) get one line naming the file, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "core/io/volume_vdb.h"

namespace frameless {
namespace {

const std::string kData = std::string(FRAMELESS_TEST_DATA) + "/volumes/";

std::string bytes_of(const std::string& name) {
  std::ifstream f(kData + name, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

Result<VdbVolume> decode(const std::string& bytes, const std::string& grid = "") {
  return decode_vdb(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "t.vdb", grid);
}

// The fixture's fog values (make_vdb_fixtures.cpp).
float fog_value(int i, int j, int k) { return float(((i * 7 + j * 13 + k * 29) % 97 + 97) % 97) / 97.0f; }

// Voxel (i, j, k) of OpenVDB's index space, or the background outside the grid.
float voxel(const VdbVolume& v, int i, int j, int k, float background) {
  const VolumeGrid& g = *v.bricked.grid;
  const int x = i - v.bricked.origin[0], y = j - v.bricked.origin[1], z = k - v.bricked.origin[2];
  if (x < 0 || y < 0 || z < 0 || x >= g.nx || y >= g.ny || z >= g.nz) return background;
  return g.at(x, y, z);
}

TEST(VdbReader, LevelSetSphereInEveryCompression) {
  auto none = read_vdb(kData + "sphere_ls_none.vdb", "");
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_EQ(none->name, "surface");
  EXPECT_EQ(none->grid_class, "level set");
  const VolumeGrid& g = *none->bricked.grid;
  ASSERT_TRUE(g.bricks);
  EXPECT_LT(g.bricks->stored(), g.bricks->table.size()) << "sparsity kept";
  // Voxels of 0.5: the band's values are the distance to the sphere of radius 3 at (6, 5.5, 6.25).
  const Affine to_world = none->grid_to_world();
  EXPECT_FLOAT_EQ(to_world.m[0][0], 0.5f);
  int band = 0;
  for (int z = 0; z < g.nz; ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x) {
        const float v = g.at(x, y, z);
        ASSERT_GE(v, -1.5f);  // the background: half width 3 of voxels 0.5
        ASSERT_LE(v, 1.5f);
        if (std::abs(v) >= 1.5f) continue;
        const Vec3 w = to_world.point(Vec3(float(x), float(y), float(z)));
        ASSERT_NEAR(v, glm::length(w - Vec3(6.0f, 5.5f, 6.25f)) - 3.0f, 0.05f) << x << " " << y << " " << z;
        ++band;
      }
  EXPECT_GT(band, 2000);
  for (const char* name : {"sphere_ls_mask.vdb", "sphere_ls_zip.vdb", "sphere_ls_blosc.vdb", "sphere_ls_half.vdb"}) {
    SCOPED_TRACE(name);
    auto other = read_vdb(kData + name, "");
    ASSERT_TRUE(other) << other.error().message;
    const VolumeGrid& o = *other->bricked.grid;
    ASSERT_EQ(other->bricked.origin, none->bricked.origin);
    ASSERT_EQ(o.nx, g.nx);
    ASSERT_EQ(o.ny, g.ny);
    ASSERT_EQ(o.nz, g.nz);
    const bool half = std::string(name) == "sphere_ls_half.vdb";
    for (int z = 0; z < g.nz; ++z)
      for (int y = 0; y < g.ny; ++y)
        for (int x = 0; x < g.nx; ++x)
          if (half)
            ASSERT_NEAR(o.at(x, y, z), g.at(x, y, z), 1e-3f);  // 11 bits of mantissa
          else
            ASSERT_EQ(o.at(x, y, z), g.at(x, y, z));
  }
}

TEST(VdbReader, FogVoxelsTilesAndInactiveValuesExactly) {
  for (const char* name : {"fog_zip.vdb", "fog_blosc.vdb"}) {
    SCOPED_TRACE(name);
    auto v = read_vdb(kData + name, "");  // fog_zip.vdb starts with a vector grid: skipped
    ASSERT_TRUE(v) << v.error().message;
    EXPECT_EQ(v->name, "density");
    EXPECT_EQ(v->grid_class, "fog volume");
    EXPECT_FLOAT_EQ(v->grid_to_world().m[1][1], 0.25f);
    for (int i = -8; i <= 34; ++i)
      for (int j = -2; j <= 14; ++j)
        for (int k = -22; k <= -5; ++k) {
          float want = 0.0f;
          if (i >= -5 && i <= 9 && j >= 3 && j <= 12 && k >= -20 && k <= -8) want = fog_value(i, j, k);
          if (i >= 16 && i <= 31 && j >= 0 && j <= 7 && k >= -16 && k <= -9) want = 0.25f;  // the tiles
          if (i == 9 && j == 12 && k == -7) want = 0.75f;                                   // inactive, kept
          ASSERT_EQ(voxel(*v, i, j, k, 0.0f), want) << i << " " << j << " " << k;
        }
  }
}

TEST(VdbReader, GridsAreChosenByNameAndMapsComeThrough) {
  const std::string fog = bytes_of("fog_zip.vdb");
  auto t = decode(fog, "temperature");  // a double grid
  ASSERT_TRUE(t) << t.error().message;
  EXPECT_EQ(voxel(*t, 1, 2, 3, 0.0f), 0.5f);
  EXPECT_EQ(voxel(*t, 2, 2, 3, 0.0f), 1.5f);
  auto vel = decode(fog, "velocity");
  ASSERT_FALSE(vel);
  EXPECT_EQ(vel.error().message, "t.vdb: grid 'velocity' holds Tree_vec3s_5_4_3 (float and double grids are read)");
  auto none = decode(fog, "pressure");
  ASSERT_FALSE(none);
  EXPECT_EQ(none.error().message,
            "t.vdb: no grid named 'pressure' (the file holds velocity (Tree_vec3s_5_4_3), density (Tree_float_5_4_3), "
            "temperature (Tree_double_5_4_3))");
  // The affine fixture: scale (0.5, 0.25, 0.5), 30 degrees about z, then (1, 2, 3).
  auto a = read_vdb(kData + "fog_affine.vdb", "");
  ASSERT_TRUE(a) << a.error().message;
  const Vec3 o = a->index_to_world.point(Vec3(0.0f)), ex = a->index_to_world.point(Vec3(1, 0, 0)) - o,
             ey = a->index_to_world.point(Vec3(0, 1, 0)) - o, ez = a->index_to_world.point(Vec3(0, 0, 1)) - o;
  EXPECT_NEAR(glm::distance(o, Vec3(1, 2, 3)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(ex), 0.5f, 1e-6f);
  EXPECT_NEAR(glm::length(ey), 0.25f, 1e-6f);
  EXPECT_NEAR(std::abs(ex.x) / 0.5f, std::cos(3.14159265f / 6.0f), 1e-5f);
  EXPECT_NEAR(glm::dot(ex, ey), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(ez, Vec3(0, 0, 0.5f)), 0.0f, 1e-6f);
  const Vec3 g = a->grid_to_world().point(Vec3(0.0f));
  EXPECT_NEAR(glm::distance(g, a->index_to_world.point(Vec3(a->bricked.origin[0], a->bricked.origin[1], a->bricked.origin[2]))), 0.0f, 1e-5f);
}

TEST(VdbReader, BrokenFilesGetOneLine) {
  const std::string good = bytes_of("sphere_ls_blosc.vdb");
  ASSERT_GT(good.size(), 10000u);
  const auto refused = [](const Result<VdbVolume>& r, const std::string& part) {
    if (r) return ::testing::AssertionFailure() << "accepted";
    const std::string& m = r.error().message;
    if (m.rfind("t.vdb: ", 0) != 0 || m.find('\n') != std::string::npos || m.find(part) == std::string::npos)
      return ::testing::AssertionFailure() << m;
    return ::testing::AssertionSuccess();
  };
  EXPECT_TRUE(refused(decode("not a vdb file at all"), "not an OpenVDB file"));
  std::string old = good;
  old[8] = char(221);
  EXPECT_TRUE(refused(decode(old), "file version 221 (OpenVDB before 3.0) is not read"));
  // Every cut of the file is refused: the header byte by byte, then every 61st length.
  for (size_t n = 0; n < good.size(); n += n < 600 ? 1 : 61) ASSERT_TRUE(refused(decode(good.substr(0, n)), "")) << n;
  // Corrupted bytes anywhere: a clean error or a grid, never a crash (ASan and UBSan watch). Every
  // 31st byte: the fuzzer (tests/fuzz, input kind 13) mutates the same reader at random besides.
  size_t errors = 0;
  for (size_t at = 0; at < good.size(); at += 31)
    for (char flip : {char(0xff), char(0x00), char(0x5a)}) {
      std::string bad = good;
      bad[at] = char(bad[at] ^ flip);
      const auto r = decode(bad);
      if (!r) {
        ++errors;
        ASSERT_TRUE(refused(r, "")) << at;
      }
    }
  EXPECT_GT(errors, 100u);
  // A Blosc chunk's header claiming more than it holds.
  std::string chunk = good;
  const size_t blosc = chunk.find(std::string("\x02\x01", 2), 400);  // Blosc version 2, format 1
  ASSERT_NE(blosc, std::string::npos);
  chunk[blosc + 12] = char(0x7f);
  EXPECT_TRUE(refused(decode(chunk), "Blosc"));
}

}  // namespace
}  // namespace frameless
