// Parker's isosurfaces (core/volume/isosurface.h): the first crossing of the trilinear interpolant
// against an independent double-precision search, no cracks at cell faces and edges, normals from
// the interpolant's gradient, and macrocells that never change a hit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include "core/volume/isosurface.h"
#include "core/volume/marching_tetrahedra.h"
#include "core/volume/volume_generators.h"

namespace frameless {
namespace {

// The interpolant in double precision, written independently of the library (corner by corner).
double interp(const VolumeGrid& g, double x, double y, double z) {
  const int i = std::clamp(int(std::floor(x)), 0, g.nx - 2), j = std::clamp(int(std::floor(y)), 0, g.ny - 2),
            k = std::clamp(int(std::floor(z)), 0, g.nz - 2);
  const double u = x - i, v = y - j, w = z - k;
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const int a = c & 1, b = (c >> 1) & 1, e = (c >> 2) & 1;
    sum += double(g.at(i + a, j + b, k + e)) * (a ? u : 1 - u) * (b ? v : 1 - v) * (e ? w : 1 - w);
  }
  return sum;
}

// The first crossing by fine steps (1/64 voxel) and bisection to 1e-9, in double.
bool reference_root(const VolumeGrid& g, double iso, const Vec3& o, const Vec3& d, double t0, double t1, double& t) {
  const auto f = [&](double s) { return interp(g, o.x + s * d.x, o.y + s * d.y, o.z + s * d.z) - iso; };
  const double len = glm::length(d), h = 1.0 / 64.0 / len;
  double a = t0, fa = f(a);
  for (double b = t0 + h; a < t1; b = std::min(t1, b + h)) {
    const double fb = f(b);
    if ((fa < 0) != (fb < 0)) {
      while (b - a > 1e-9) {
        const double m = 0.5 * (a + b), fm = f(m);
        if ((fm < 0) == (fa < 0)) a = m, fa = fm;
        else b = m;
      }
      t = 0.5 * (a + b);
      return true;
    }
    a = b;
    fa = fb;
    if (b >= t1) break;
  }
  return false;
}

bool clip(const VolumeGrid& g, const Vec3& o, const Vec3& d, float& t0, float& t1) {
  t0 = 0.0f;
  t1 = 1e30f;
  return clip_to_box(Vec3(0.0f), Vec3(float(g.nx - 1), float(g.ny - 1), float(g.nz - 1)), o, d, t0, t1);
}

TEST(Isosurface, FirstCrossingAgreesWithADoublePrecisionSearch) {
  const auto g = make_sphere_distance(24);
  const Macrocells m = build_macrocells(*g);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Vec3 c(11.5f);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    // From a point well outside towards a point inside the sphere of radius 8 (not grazing).
    Vec3 from(u(rng), u(rng), u(rng)), to(u(rng), u(rng), u(rng));
    if (glm::length(from) < 1e-3f) continue;
    from = c + glm::normalize(from) * 30.0f;
    to = c + to * 4.0f;
    const Vec3 d = to - from;  // not unit: t is in units of this vector
    float t0, t1;
    ASSERT_TRUE(clip(*g, from, d, t0, t1));
    double want;
    ASSERT_TRUE(reference_root(*g, 8.0, from, d, t0, t1, want)) << i;
    float got;
    ASSERT_TRUE(intersect_isosurface(*g, &m, 8.0f, from, d, 0.0f, 1e30f, got)) << i;
    EXPECT_NEAR(got * glm::length(d), want * glm::length(d), 1e-3) << "ray " << i;  // in voxels
    ++hits;
  }
  EXPECT_GT(hits, 2900);
}

TEST(Isosurface, NoCracksAtCellFacesEdgesAndCorners) {
  const auto g = make_sphere_distance(20);
  const Macrocells m = build_macrocells(*g, 4);
  const Vec3 c(9.5f);
  int tested = 0;
  for (int a = 4; a <= 15; ++a)
    for (int b = 4; b <= 15; ++b)
      for (int kind = 0; kind < 3; ++kind) {
        // Axis-aligned and diagonal rays through integer lines and points: cell faces and edges.
        Vec3 from, d;
        if (kind == 0) from = Vec3(float(a), float(b), -5.0f), d = Vec3(0, 0, 1);
        if (kind == 1) from = Vec3(float(a), -5.0f, float(b)), d = glm::normalize(Vec3(0, 1, 1e-7f));
        if (kind == 2) from = Vec3(float(a) - 5.0f, float(b) - 5.0f, -5.0f + float(a - b)), d = glm::normalize(Vec3(1, 1, 1));
        float t0, t1;
        if (!clip(*g, from, d, t0, t1)) continue;
        double want;
        const bool ref = reference_root(*g, 6.0, from, d, t0, t1, want);
        float got;
        const bool hit = intersect_isosurface(*g, &m, 6.0f, from, d, 0.0f, 1e30f, got);
        ASSERT_EQ(hit, ref) << a << "," << b << " kind " << kind;
        if (hit) EXPECT_NEAR(got, want, 1e-3) << a << "," << b << " kind " << kind;
        ++tested;
      }
  EXPECT_GT(tested, 300);
  (void)c;
}

TEST(Isosurface, GradientIsTheInterpolantsDerivative) {
  const auto g = make_marschner_lobb(17);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.5f, 15.5f);
  for (int i = 0; i < 500; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    // Central differences inside the cell (the interpolant is smooth there).
    const Vec3 cell = glm::floor(p);
    const Vec3 q = glm::clamp(p, cell + 0.01f, cell + 0.99f);
    const Vec3 grad = trilinear_gradient(*g, q);
    const double h = 1e-4;
    for (int ax = 0; ax < 3; ++ax) {
      Vec3 e(0.0f);
      e[ax] = 1.0f;
      const double num = (interp(*g, q.x + h * e.x, q.y + h * e.y, q.z + h * e.z) -
                          interp(*g, q.x - h * e.x, q.y - h * e.y, q.z - h * e.z)) / (2 * h);
      EXPECT_NEAR(grad[ax], num, 1e-4 + 1e-3 * std::abs(num)) << i << " axis " << ax;
    }
    EXPECT_NEAR(trilinear_value(*g, q), interp(*g, q.x, q.y, q.z), 1e-5);
  }
}

TEST(Isosurface, MacrocellsNeverChangeAHit) {
  for (const char* name : {"volume:marschner-lobb:33", "volume:shepp-logan:48"}) {
    const auto g = *make_builtin_volume(name);
    const Macrocells m = build_macrocells(*g);
    const float iso = std::string(name).find("shepp") != std::string::npos ? 1200.0f : 0.5f;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    const Vec3 top(float(g->nx - 1), float(g->ny - 1), float(g->nz - 1));
    int hits = 0, skipped_cells = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec3 from = Vec3(u(rng), u(rng), u(rng)) * top * 2.0f - top * 0.5f;
      const Vec3 to = Vec3(u(rng), u(rng), u(rng)) * top;
      const Vec3 d = glm::normalize(to - from);
      float a = 0, b = 0;
      const bool ha = intersect_isosurface(*g, &m, iso, from, d, 0.0f, 1e30f, a);
      const bool hb = intersect_isosurface(*g, nullptr, iso, from, d, 0.0f, 1e30f, b);
      ASSERT_EQ(ha, hb) << name << " ray " << i;
      if (ha) EXPECT_EQ(a, b) << name << " ray " << i;  // the same cells, entered at the same t
      hits += ha;
    }
    EXPECT_GT(hits, 500) << name;
    for (size_t k = 0; k < m.lo.size(); ++k) skipped_cells += !(m.lo[k] <= iso && iso <= m.hi[k]);
    EXPECT_GT(skipped_cells, 0) << name;  // the test has power: some macrocells are skipped
  }
}

TEST(MarchingTetrahedra, MeshesTheSphereWithOutwardFaces) {
  const auto g = make_sphere_distance(24);
  const Macrocells m = build_macrocells(*g);
  const Vec3 c(11.5f);
  const IsoMesh mesh = marching_tetrahedra(*g, m, 8.0f, false);  // inside: below (a distance field)
  ASSERT_GT(mesh.positions.size(), 3000u);
  ASSERT_EQ(mesh.positions.size() % 3, 0u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); i += 3) {
    const Vec3 &a = mesh.positions[i], &b = mesh.positions[i + 1], &d = mesh.positions[i + 2];
    for (const Vec3& p : {a, b, d}) ASSERT_NEAR(glm::length(p - c), 8.0f, 0.1f);  // on the sphere
    const Vec3 out = glm::normalize((a + b + d) / 3.0f - c);
    EXPECT_GT(glm::dot(glm::normalize(glm::cross(b - a, d - a)), out), 0.5f) << i;  // wound outwards
    EXPECT_GT(glm::dot(mesh.normals[i], out), 0.95f) << i;                          // gradient normals
  }
  // The macrocells skip nothing that holds the isovalue: the same mesh without skipping anything.
  Macrocells all = m;
  std::fill(all.lo.begin(), all.lo.end(), g->min_value);
  std::fill(all.hi.begin(), all.hi.end(), g->max_value);
  EXPECT_EQ(marching_tetrahedra(*g, all, 8.0f, false).positions.size(), mesh.positions.size());
}

TEST(Generators, NamesSizesAndValues) {
  auto ml = make_builtin_volume("volume:marschner-lobb:41");
  ASSERT_TRUE(ml) << ml.error().message;
  EXPECT_EQ((*ml)->nx, 41);
  EXPECT_NEAR((*ml)->at(20, 20, 20), marschner_lobb(0, 0, 0), 1e-6);
  auto sl = make_builtin_volume("volume:shepp-logan:64x48x80");
  ASSERT_TRUE(sl) << sl.error().message;
  EXPECT_EQ((*sl)->type, VoxelType::kUint16);
  EXPECT_EQ((*sl)->nz, 80);
  EXPECT_EQ((*sl)->at(0, 0, 0), 0.0f);                       // outside the head
  EXPECT_NEAR((*sl)->at(32, 24, 40), 0.2f * 4000.0f, 5.0f);  // brain: 1 - 0.8 (smoothed: integer rounding)
  for (const char* bad : {"volume:torus:8", "volume:sphere:1", "volume:sphere:x", "volume:sphere:8x8x8",
                          "volume:shepp-logan:8x8", "volume:sphere:99999", "volume:sphere:8x",
                          "volume:sphere:1024" /* 4 GiB */}) {
    auto r = make_builtin_volume(bad);
    ASSERT_FALSE(r) << bad;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
    EXPECT_EQ(r.error().message.rfind(bad, 0), 0u) << r.error().message;
  }
}

// Scene loading generates volumes and their macrocells through its default executor: any
// executor (here one running the tasks backwards) must give the serial voxels and ranges.
TEST(VolumeGenerators, AnExecutorGivesTheSerialVoxels) {
  const ParallelFor backwards = [](size_t n, const std::function<void(size_t)>& body) {
    for (size_t i = n; i-- > 0;) body(i);
  };
  for (const char* name : {"volume:marschner-lobb:33", "volume:shepp-logan:40x36x44", "volume:sphere:30"}) {
    SCOPED_TRACE(name);
    auto serial = make_builtin_volume(name);
    auto parallel = make_builtin_volume(name, backwards);
    ASSERT_TRUE(serial.ok() && parallel.ok());
    const VolumeGrid &a = **serial, &b = **parallel;
    ASSERT_EQ(a.bytes(), b.bytes());
    EXPECT_EQ(std::memcmp(a.storage->data(), b.storage->data(), a.bytes()), 0);
    EXPECT_EQ(a.min_value, b.min_value);
    EXPECT_EQ(a.max_value, b.max_value);
    const Macrocells ms = build_macrocells(a), mp = build_macrocells(a, 8, backwards);
    EXPECT_EQ(ms.lo, mp.lo);
    EXPECT_EQ(ms.hi, mp.hi);
  }
}

}  // namespace
}  // namespace frameless
