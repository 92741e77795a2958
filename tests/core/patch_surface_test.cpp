// The direct ray intersector of bicubic Bézier patches (PatchSurface: Broyden in a per-patch BVH)
// against a fine tessellation, across seams, and its iteration count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/bezier.h"
#include "core/geometry/intersect_triangle.h"
#include "core/io/patch_io.h"

#include "bezier_patches.h"

namespace frameless {
namespace {

using test_util::cap_patch;
using test_util::curved_patch;
using test_util::DVec3;
using test_util::flat_patch;
using test_util::ref_point;
using test_util::teapot;
using test_util::tube_patch;

double patch_size(const BezierPatch& p) {
  Vec3 lo = p.p[0], hi = p.p[0];
  for (const Vec3& q : p.p) lo = glm::min(lo, q), hi = glm::max(hi, q);
  return glm::length(hi - lo);
}

Ray make_ray(const Vec3& org, const Vec3& dir) {
  Ray r;
  r.org = org;
  r.dir = dir;
  return r;
}

// A fine tessellation (n x n quads, two watertight triangles each), intersected by brute force
// with a box per block of 16 x 16 quads to keep the suite fast.
class Tessellation {
 public:
  explicit Tessellation(const BezierPatch& p, int n = 128) : n_(n), grid_(size_t(n + 1) * (n + 1)) {
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) grid_[size_t(i) * (n + 1) + j] = Vec3(ref_point(p, double(j) / n, double(i) / n));
    for (int bi = 0; bi < n; bi += kBlock)
      for (int bj = 0; bj < n; bj += kBlock) {
        Vec3 lo(kInfinity), hi(-kInfinity);
        for (int i = bi; i <= bi + kBlock; ++i)
          for (int j = bj; j <= bj + kBlock; ++j) lo = glm::min(lo, at(i, j)), hi = glm::max(hi, at(i, j));
        blocks_.push_back({lo - 1e-4f, hi + 1e-4f, bi, bj});
      }
  }

  // Closest hit: t, the patch parameters and the triangle's unit normal.
  bool intersect(const Ray& ray, float& t, float& u, float& v, Vec3& normal) const {
    const TriangleRay tr = make_triangle_ray(ray);
    t = kInfinity;
    bool hit = false;
    for (const Block& b : blocks_) {
      if (!box_hit(ray, b.lo, b.hi, t)) continue;
      for (int i = b.i; i < b.i + kBlock; ++i)
        for (int j = b.j; j < b.j + kBlock; ++j) {
          // Triangles (i,j) (i,j+1) (i+1,j+1) and (i,j) (i+1,j+1) (i+1,j).
          const int corner[2][2][2] = {{{0, 1}, {1, 1}}, {{1, 1}, {1, 0}}};
          for (const auto& tri : corner) {
            const Vec3 &p0 = at(i, j), &p1 = at(i + tri[0][0], j + tri[0][1]), &p2 = at(i + tri[1][0], j + tri[1][1]);
            float tt, b1, b2;
            if (!intersect_triangle(tr, p0, p1, p2, 0.0f, t, tt, b1, b2)) continue;
            hit = true, t = tt;
            u = (j + b1 * tri[0][1] + b2 * tri[1][1]) / float(n_);
            v = (i + b1 * tri[0][0] + b2 * tri[1][0]) / float(n_);
            normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
          }
        }
    }
    return hit;
  }

 private:
  static constexpr int kBlock = 16;
  struct Block {
    Vec3 lo, hi;
    int i, j;
  };
  const Vec3& at(int i, int j) const { return grid_[size_t(i) * (n_ + 1) + j]; }
  static bool box_hit(const Ray& r, const Vec3& lo, const Vec3& hi, float tmax) {
    float t0 = 0.0f, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
      const float inv = 1.0f / r.dir[a];
      const float tl = (lo[a] - r.org[a]) * inv, th = (hi[a] - r.org[a]) * inv;
      t0 = std::max(t0, std::min(tl, th));
      t1 = std::min(t1, std::max(tl, th));
    }
    return t0 <= t1;
  }
  int n_;
  std::vector<Vec3> grid_;
  std::vector<Block> blocks_;
};

// The tessellation's hit polished by Newton's method on the exact surface (double, Jacobian by
// central differences): the tessellation picks the root (the closest crossing), the polish
// removes its chord error, which grazing rays amplify beyond the tolerance under test. Keeps the
// tessellation's t when the polish does not settle next to it.
float polish(const BezierPatch& p, const Ray& ray, float t0, float u0, float v0) {
  const DVec3 o(ray.org), d(ray.dir);
  double u = u0, v = v0, t = t0;
  const double h = 1e-6, tol = 1e-12 * patch_size(p);
  for (int k = 0; k < 30; ++k) {
    const DVec3 f = ref_point(p, u, v) - (o + t * d);
    if (glm::length(f) <= tol) {
      const bool near = std::abs(t - t0) <= 1e-3 * std::abs(t0) && u > -1e-3 && u < 1.001 && v > -1e-3 && v < 1.001;
      return near ? float(t) : t0;
    }
    const DVec3 pu = (ref_point(p, u + h, v) - ref_point(p, u - h, v)) / (2 * h);
    const DVec3 pv = (ref_point(p, u, v + h) - ref_point(p, u, v - h)) / (2 * h);
    const glm::dmat3 j(pu, pv, -d);
    if (std::abs(glm::determinant(j)) < 1e-300) break;
    const DVec3 dx = glm::inverse(j) * -f;
    u += dx.x, v += dx.y, t += dx.z;
  }
  return t0;
}

// Camera-like rays: from a few viewpoints around the patch, through random points of its
// bounding box (so about uniform over the image of the box, hits and misses).
std::vector<Ray> camera_rays(const BezierPatch& p, int views, int per_view, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  Vec3 lo = p.p[0], hi = p.p[0];
  for (const Vec3& q : p.p) lo = glm::min(lo, q), hi = glm::max(hi, q);
  const Vec3 c = 0.5f * (lo + hi), ext = hi - lo;
  const float radius = 2.5f * glm::length(ext);
  std::vector<Ray> rays;
  for (int k = 0; k < views; ++k) {
    Vec3 dir;
    do dir = 2.0f * Vec3(uni(rng), uni(rng), uni(rng)) - 1.0f;
    while (glm::length(dir) > 1.0f || glm::length(dir) < 0.1f);
    const Vec3 o = c + radius * glm::normalize(dir);
    for (int m = 0; m < per_view; ++m) {
      const Vec3 target = lo - 0.1f * ext + 1.2f * ext * Vec3(uni(rng), uni(rng), uni(rng));
      rays.push_back(make_ray(o, target - o));
    }
  }
  return rays;
}

struct Agreement {
  int rays = 0, both = 0, depth_ok = 0, hit_miss = 0, hit_miss_off_silhouette = 0;
  double worst = 0.0;
};

// Near a silhouette: a grazing hit, or one next to the patch's boundary (an open patch's outline).
bool near_silhouette(const Vec3& normal, const Ray& ray, float u, float v) {
  const float cosine = std::abs(glm::dot(normal, glm::normalize(ray.dir)));
  const float edge = std::min(std::min(u, 1.0f - u), std::min(v, 1.0f - v));
  return cosine < 0.15f || edge < 0.02f;
}

Agreement compare(const BezierPatch& p, int depth, uint32_t seed, double rel_tol) {
  const PatchSurface surface(p, depth);
  const Tessellation mesh(p);
  Agreement a;
  for (const Ray& ray : camera_rays(p, 8, 40, seed)) {
    ++a.rays;
    float t, u, v, tm, um = 0.0f, vm = 0.0f;
    Vec3 nm(0.0f);
    const bool hit = surface.intersect(ray, 0.0f, kInfinity, t, u, v);
    const bool hit_mesh = mesh.intersect(ray, tm, um, vm, nm);
    if (hit && hit_mesh) {
      ++a.both;
      const float ref = polish(p, ray, tm, um, vm);
      const double rel = std::abs(double(t) - ref) / ref;
      a.worst = std::max(a.worst, rel);
      a.depth_ok += rel <= rel_tol;
    } else if (hit != hit_mesh) {
      ++a.hit_miss;
      const bool near = hit ? near_silhouette(bezier_normal(p, u, v), ray, u, v) : near_silhouette(nm, ray, um, vm);
      a.hit_miss_off_silhouette += !near;
    }
  }
  return a;
}

// Depth within 1e-4 (relative) on at least 99% of the rays that both hit, over a set of patches
// (at least 95% on each), and no hit/miss difference away from silhouettes.
void expect_agreement(const std::vector<std::pair<std::string, BezierPatch>>& set, uint32_t seed) {
  const double kRelTol = 1e-4;
  int both = 0, depth_ok = 0;
  for (const auto& [name, patch] : set) {
    const Agreement a = compare(patch, 4, seed++, kRelTol);
    std::printf("  %-10s rays %d, both hit %d, depth within %.0e: %d (worst %.2e), hit/miss differ %d (%d off silhouettes)\n",
                name.c_str(), a.rays, a.both, kRelTol, a.depth_ok, a.worst, a.hit_miss, a.hit_miss_off_silhouette);
    ASSERT_GT(a.both, a.rays / 10) << name << ": the rays should hit the patch";
    EXPECT_GE(a.depth_ok, 0.95 * a.both) << name;
    EXPECT_EQ(a.hit_miss_off_silhouette, 0) << name;
    EXPECT_LE(a.hit_miss, a.rays / 50) << name;
    both += a.both, depth_ok += a.depth_ok;
  }
  EXPECT_GE(depth_ok, 0.99 * both);
}

TEST(PatchSurface, AgreesWithFineTessellation) {
  expect_agreement({{"flat", flat_patch()}, {"curved", curved_patch()}, {"tube", tube_patch()}, {"cap", cap_patch()}}, 1);
}

TEST(PatchSurface, TeapotAgreesWithFineTessellation) {
  auto patches = teapot();
  if (!patches) GTEST_SKIP() << "no teapot (apt-get install povray-examples): " << patches.error().message;
  // Rim, body, handle, spout tip, lid knob (pole), lid, bottom (pole).
  std::vector<std::pair<std::string, BezierPatch>> set;
  for (int k : {0, 4, 12, 18, 20, 24, 28}) set.push_back({"teapot " + std::to_string(k), (*patches)[k]});
  expect_agreement(set, 100);
}

// Rays from outside aimed at points of the shared edge of patches a and b (edge: 0 v=0, 1 v=1,
// 2 u=0, 3 u=1 of a), from directions tilted up to 45 degrees off the mean normal; returns how
// many pass through both.
int seam_leaks(const BezierPatch& a, int edge, const BezierPatch& b, float overlap, int* tried) {
  const PatchSurface sa(a, 4, overlap), sb(b, 4, overlap);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  const float size = float(patch_size(a));
  int leaks = 0;
  for (int k = 0; k <= 64; ++k) {
    const float s = k / 64.0f;
    const float u = edge == 2 ? 0.0f : edge == 3 ? 1.0f : s, v = edge == 0 ? 0.0f : edge == 1 ? 1.0f : s;
    const Vec3 target = bezier_eval(a, u, v), n = bezier_normal(a, u, v);
    for (int m = 0; m < 4; ++m) {
      Vec3 tilt(uni(rng), uni(rng), uni(rng));
      tilt -= glm::dot(tilt, n) * n;
      const Vec3 dir = glm::normalize(n + 0.7f * tilt);
      const Ray ray = make_ray(target + 2.0f * size * dir, -dir);
      float t, pu, pv;
      ++*tried;
      const float end = 2.0f * size * (1.0f + 1e-4f);  // the seam point, or something before it
      const bool hit = sa.intersect(ray, 0.0f, end, t, pu, pv) || sb.intersect(ray, 0.0f, end, t, pu, pv);
      leaks += !hit;
    }
  }
  return leaks;
}

TEST(PatchSurface, SharedEdgeOfAdjacentPatchesHasNoCrack) {
  // Two halves of the curved patch meet at u = 0.5 with the same boundary control points; also
  // cut in v so that the seam runs through the bumps at an angle to the leaves.
  const BezierPatch p = curved_patch();
  int tried = 0;
  EXPECT_EQ(seam_leaks(bezier_subpatch(p, 0.0f, 0.5f, 0.0f, 1.0f), 3, bezier_subpatch(p, 0.5f, 1.0f, 0.0f, 1.0f),
                       0.02f, &tried), 0);
  EXPECT_EQ(seam_leaks(bezier_subpatch(p, 0.0f, 1.0f, 0.3f, 1.0f), 0, bezier_subpatch(p, 0.0f, 1.0f, 0.0f, 0.3f),
                       0.02f, &tried), 0);
  EXPECT_EQ(tried, 2 * 65 * 4);
}

TEST(PatchSurface, LeafSeamsInsideAPatchHaveNoCrack) {
  // Rays at the leaf boundaries u = k/16 and v = k/16 of one surface: the leaves' overlap is
  // what makes a root on the boundary count in at least one of the two leaves.
  const BezierPatch p = curved_patch();
  const PatchSurface s(p, 4);
  const float size = float(patch_size(p));
  int leaks = 0, tried = 0;
  for (int k = 1; k < 16; ++k)
    for (int m = 0; m <= 40; ++m) {
      for (int dir = 0; dir < 2; ++dir) {
        const float u = dir ? k / 16.0f : m / 40.0f, v = dir ? m / 40.0f : k / 16.0f;
        const Vec3 target = bezier_eval(p, u, v), n = bezier_normal(p, u, v);
        const Ray ray = make_ray(target + 2.0f * size * n, -n);
        float t, hu, hv;
        ++tried;
        leaks += !s.intersect(ray, 0.0f, 2.0f * size * (1.0f + 1e-4f), t, hu, hv);
      }
    }
  EXPECT_EQ(leaks, 0) << "of " << tried;
}

TEST(PatchSurface, TeapotSeamsHaveNoCrack) {
  auto patches = teapot();
  if (!patches) GTEST_SKIP() << "no teapot (apt-get install povray-examples): " << patches.error().message;
  // Every pair of teapot patches whose boundary control points coincide (the lid meets nothing:
  // it sits inside the rim). Edge e of a patch: 0 row 0, 1 row 3, 2 column 0, 3 column 3.
  auto edge_points = [&](int k, int e, int s) {
    const int idx = e == 0 ? s : e == 1 ? 12 + s : e == 2 ? 4 * s : 4 * s + 3;
    return (*patches)[k].p[idx];
  };
  int seams = 0, body_seams = 0, tried = 0, leaks = 0;
  for (int a = 0; a < 32; ++a)
    for (int b = a + 1; b < 32; ++b)
      for (int ea = 0; ea < 4; ++ea)
        for (int eb = 0; eb < 4; ++eb) {
          bool collapsed = true, forward = true, backward = true;
          for (int s = 0; s < 4; ++s) {
            collapsed &= edge_points(a, ea, s) == edge_points(a, ea, 0);
            forward &= edge_points(a, ea, s) == edge_points(b, eb, s);
            backward &= edge_points(a, ea, s) == edge_points(b, eb, 3 - s);
          }
          if (collapsed || !(forward || backward)) continue;
          ++seams;
          body_seams += a >= 4 && b < 12;
          const int n = seam_leaks((*patches)[a], ea, (*patches)[b], 0.02f, &tried);
          EXPECT_EQ(n, 0) << "patches " << a << " and " << b;
          leaks += n;
        }
  std::printf("  %d seams (%d inside the body), %d rays, %d through\n", seams, body_seams, tried, leaks);
  EXPECT_EQ(seams, 52);
  EXPECT_EQ(body_seams, 12);
}

// Rays aimed at points of the patch from all over the hemisphere in front of them, grazing ones
// included: each must stop at its point or before. Returns how many go through.
int aimed_misses(const BezierPatch& p, int count, uint32_t seed) {
  const PatchSurface s(p, 4);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  const float size = float(patch_size(p));
  int misses = 0;
  for (int k = 0; k < count; ++k) {
    const float u = 0.05f + 0.9f * uni(rng), v = 0.05f + 0.9f * uni(rng);
    const Vec3 target = bezier_eval(p, u, v), n = bezier_normal(p, u, v);
    Vec3 dir;
    do dir = 2.0f * Vec3(uni(rng), uni(rng), uni(rng)) - 1.0f;
    while (glm::length(dir) > 1.0f || std::abs(glm::dot(dir, n)) < 0.01f * glm::length(dir));
    dir = glm::normalize(dir) * (glm::dot(dir, n) < 0.0f ? -1.0f : 1.0f);
    const Ray ray = make_ray(target + 2.0f * size * dir, -dir);
    float t, hu, hv;
    misses += !s.intersect(ray, 0.0f, 2.0f * size * (1.0f + 1e-4f), t, hu, hv);
  }
  return misses;
}

TEST(PatchSurface, GrazingRaysStopAtTheSurface) {
  std::vector<std::pair<std::string, BezierPatch>> set = {
      {"curved", curved_patch()}, {"tube", tube_patch()}, {"cap", cap_patch()}};
  auto patches = teapot();
  if (patches)
    for (int k : {0, 4, 12, 16, 20, 24, 28}) set.push_back({"teapot " + std::to_string(k), (*patches)[k]});
  int misses = 0, rays = 0;
  for (size_t k = 0; k < set.size(); ++k) {
    const int m = aimed_misses(set[k].second, 1000, 900 + uint32_t(k));
    std::printf("  %-10s %d of 1000 aimed rays pass through\n", set[k].first.c_str(), m);
    misses += m, rays += 1000;
  }
  EXPECT_LE(misses, rays / 1000);
}

TEST(PatchSurface, BroydenConvergesInFewIterations) {
  std::vector<BezierPatch> set = {curved_patch(), tube_patch(), cap_patch()};
  auto patches = teapot();
  if (patches)
    for (int k = 0; k < 32; k += 2) set.push_back((*patches)[k]);
  PatchHitStats stats;
  for (size_t k = 0; k < set.size(); ++k) {
    const PatchSurface s(set[k], 4);
    for (const Ray& ray : camera_rays(set[k], 4, 50, 300 + uint32_t(k))) {
      float t, u, v;
      s.intersect(ray, 0.0f, kInfinity, t, u, v, &stats);
    }
  }
  const double mean = double(stats.iterations) / double(stats.converged);
  std::printf("  depth 4, %zu patches: %llu leaf boxes entered, %llu solves, %llu converged, %.2f iterations each\n",
              set.size(), (unsigned long long)stats.leaf_tests, (unsigned long long)stats.solves,
              (unsigned long long)stats.converged, mean);
  ASSERT_GT(stats.converged, 500u);
  // Broyden's rank-1 updates matter: without them (the chord method) the mean is about 3.7.
  EXPECT_LT(mean, 3.6);
}

TEST(PatchSurface, RespectsTheIntervalAndAnyHitAgrees) {
  const BezierPatch p = curved_patch();
  const PatchSurface s(p, 4);
  int hits = 0;
  for (const Ray& ray : camera_rays(p, 4, 50, 5)) {
    float t, u, v;
    const bool hit = s.intersect(ray, 0.0f, kInfinity, t, u, v);
    EXPECT_EQ(s.occluded(ray, 0.0f, kInfinity), hit);
    if (!hit) continue;
    ++hits;
    EXPECT_TRUE(u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f) << u << " " << v;
    EXPECT_LT(glm::length(bezier_eval(p, u, v) - (ray.org + t * ray.dir)), 1e-4f * float(patch_size(p)));
    float t2, u2, v2;
    // Nothing closer than the closest hit; past it, only farther hits.
    EXPECT_FALSE(s.intersect(ray, 0.0f, t * 0.999f, t2, u2, v2));
    EXPECT_FALSE(s.occluded(ray, 0.0f, t * 0.999f));
    if (s.intersect(ray, t * 1.001f, kInfinity, t2, u2, v2)) {
      EXPECT_GT(t2, t);
    }
  }
  EXPECT_GT(hits, 20);
}

TEST(PatchSurface, NodesAreOnlyBoxes) {
  const PatchSurface s(curved_patch(), 4);
  // 1 + 4 + 16 + 64 + 256 boxes of 6 floats; the leaves' parameter intervals cost nothing.
  EXPECT_GE(s.bytes(), 341u * 24u);
  EXPECT_LE(s.bytes(), 341u * 24u + sizeof(PatchSurface));
  EXPECT_EQ(PatchSurface(curved_patch(), 99).depth(), kMaxPatchDepth);
  float t, u, v;
  EXPECT_FALSE(PatchSurface().intersect(make_ray(Vec3(0), Vec3(1, 0, 0)), 0.0f, kInfinity, t, u, v));
}

}  // namespace
}  // namespace frameless
