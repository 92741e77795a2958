// Writes the OpenVDB fixtures of tests/readers/volume_vdb_test.cpp with OpenVDB itself, so the
// reader is tested against files the reference library wrote. Not part of the build (it needs
// Debian's libopenvdb-dev, libboost-dev and libboost-iostreams-dev: tools/install-deps.sh
// --fixtures installs them); run it by hand:
//   g++ -std=c++17 -O1 tests/data/volumes/make_vdb_fixtures.cpp -o /tmp/make_vdb_fixtures \
//       -lopenvdb -ltbb -lImath-3_1 && /tmp/make_vdb_fixtures tests/data/volumes
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cstdio>
#include <string>

namespace {

// The fog fixture's active values (the test computes the same).
float fog_value(int i, int j, int k) { return float(((i * 7 + j * 13 + k * 29) % 97 + 97) % 97) / 97.0f; }

void write(const std::string& path, openvdb::GridPtrVec grids, uint32_t compression) {
  openvdb::io::File file(path);
  file.setCompression(compression);
  file.write(grids);
  file.close();
  std::printf("%s\n", path.c_str());
}

openvdb::FloatGrid::Ptr fog() {
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setName("density");
  g->setGridClass(openvdb::GRID_FOG_VOLUME);
  auto acc = g->getAccessor();
  for (int i = -5; i <= 9; ++i)
    for (int j = 3; j <= 12; ++j)
      for (int k = -20; k <= -8; ++k) acc.setValueOn(openvdb::Coord(i, j, k), fog_value(i, j, k));
  // Two leaf-sized tiles (active, 0.25) and an inactive voxel that is not the background.
  g->tree().fill(openvdb::CoordBBox(openvdb::Coord(16, 0, -16), openvdb::Coord(31, 7, -9)), 0.25f, true);
  acc.setValueOff(openvdb::Coord(9, 12, -7), 0.75f);
  g->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const std::string dir = argv[1];
  openvdb::initialize();
  using openvdb::io::COMPRESS_ACTIVE_MASK;
  using openvdb::io::COMPRESS_BLOSC;
  using openvdb::io::COMPRESS_NONE;
  using openvdb::io::COMPRESS_ZIP;

  // A narrow-band level set: radius 3 at (6, 5.5, 6.25) (one root child), voxels of 0.5, half width 3.
  auto sphere = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(3.0f, openvdb::Vec3f(6.0f, 5.5f, 6.25f), 0.5f, 3.0f);
  sphere->setName("surface");
  write(dir + "/sphere_ls_none.vdb", {sphere}, COMPRESS_NONE);
  write(dir + "/sphere_ls_mask.vdb", {sphere}, COMPRESS_ACTIVE_MASK);
  write(dir + "/sphere_ls_zip.vdb", {sphere}, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK);
  write(dir + "/sphere_ls_blosc.vdb", {sphere}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  auto half = sphere->deepCopy();
  half->setSaveFloatAsHalf(true);
  write(dir + "/sphere_ls_half.vdb", {half}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);

  // A fog volume beside a vector grid and a temperature grid in one file.
  auto density = fog();
  auto temperature = openvdb::DoubleGrid::create(0.0);
  temperature->setName("temperature");
  temperature->getAccessor().setValueOn(openvdb::Coord(1, 2, 3), 0.5);
  temperature->getAccessor().setValueOn(openvdb::Coord(2, 2, 3), 1.5);
  auto velocity = openvdb::Vec3SGrid::create();
  velocity->setName("velocity");
  velocity->getAccessor().setValueOn(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
  write(dir + "/fog_zip.vdb", {velocity, density, temperature}, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK);
  write(dir + "/fog_blosc.vdb", {density}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  // An affine map: rotated 30 degrees about z, scaled and moved.
  auto turned = fog();
  openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
  m.preScale(openvdb::Vec3d(0.5, 0.25, 0.5));
  m.postRotate(openvdb::math::Z_AXIS, 3.14159265358979 / 6.0);
  m.postTranslate(openvdb::Vec3d(1.0, 2.0, 3.0));
  turned->setTransform(openvdb::math::Transform::createLinearTransform(m));
  write(dir + "/fog_affine.vdb", {turned}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  return 0;
}
