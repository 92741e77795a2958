// Instancing: an instanced scene renders what the same geometry flattened renders (rays in
// instance space are not bit-exact: within a stated tolerance), mirrored and non-uniformly
// scaled instances keep true normals, packets agree with single rays, cut-outs work.
#include <gtest/gtest.h>

#include <cmath>

#include "core/accel/instance.h"
#include "core/accel/instance_top.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scene/scene_intersect.h"
#include "core/scenes/builtin_scenes.h"
#include "core/shading/render_sample.h"

namespace frameless {
namespace {

// A unit sphere as a triangle mesh (latitude-longitude), outward winding.
Geometry sphere_mesh(int rings, int sides, uint16_t material) {
  Geometry g;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i <= sides; ++i) {
      const float th = kPi * float(j) / float(rings), ph = 2.0f * kPi * float(i) / float(sides);
      g.positions.push_back(Vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
    }
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < sides; ++i) {
      const uint32_t a = uint32_t(j * (sides + 1) + i), b = a + 1, c = a + uint32_t(sides + 1), d = c + 1;
      g.triangles.push_back({a, b, d});
      g.triangles.push_back({a, d, c});
    }
  g.triangle_material.assign(g.triangles.size(), material);
  return g;
}

Affine placement(int k) {
  Affine a;
  const float c = std::cos(0.7f * float(k)), s = std::sin(0.7f * float(k));
  // Rotation, non-uniform scale, and every third one mirrored in x.
  const Vec3 scale(k % 3 == 0 ? -1.3f : 1.3f, 0.6f + 0.1f * float(k % 4), 0.9f);
  a.m = glm::mat3(Vec3(c, 0, -s), Vec3(0, 1, 0), Vec3(s, 0, c)) * glm::mat3(
      Vec3(scale.x, 0, 0), Vec3(0, scale.y, 0), Vec3(0, 0, scale.z));
  a.t = Vec3(2.6f * float(k % 4) - 4.0f, 0.8f, -2.6f * float(k / 4));
  return a;
}

// The same scene two ways: a floor, plus `n` placements of a sphere mesh as instances or as
// flattened copies with transformed vertices.
std::unique_ptr<Scene> make(bool instanced, int n) {
  auto s = std::make_unique<Scene>();
  const uint16_t floor = add_material(*s, diffuse("floor", Vec3(0.6f)));
  const uint16_t shiny = add_material(*s, polished("shiny", Vec3(0.7f, 0.3f, 0.2f), 0.05f));
  add_quad(*s, Vec3(0, 0, -4), Vec3(0, 1, 0), 30.0f, floor);
  auto mesh = std::make_shared<InstancedMesh>();
  mesh->geometry = sphere_mesh(24, 32, shiny);
  build_instanced_mesh(*mesh);
  for (int k = 0; k < n; ++k) {
    const Affine a = placement(k);
    if (instanced) {
      Instance inst;
      EXPECT_TRUE(make_instance(0, a, inst));
      s->geometry.instances.push_back(inst);
    } else {
      Geometry& g = s->geometry;
      const uint32_t base = uint32_t(g.positions.size());
      for (const Vec3& p : mesh->geometry.positions) g.positions.push_back(a.point(p));
      const bool mirrored = glm::determinant(a.m) < 0.0f;  // keep the outward winding
      for (const UVec3& t : mesh->geometry.triangles)
        g.triangles.push_back(mirrored ? UVec3(base + t.x, base + t.z, base + t.y) : UVec3(t) + base);
      g.triangle_material.insert(g.triangle_material.end(), mesh->geometry.triangles.size(), shiny);
    }
  }
  if (instanced) s->geometry.instance_meshes.push_back(mesh);
  s->lights.push_back(Light{Vec3(3, 9, 6), Vec3(0.9f), 0.0f});
  s->ambient = default_hemisphere_ambient();
  s->camera.eye = Vec3(0, 5, 7);
  s->camera.look = Vec3(0, 0.5f, -3);
  s->settings.background = Vec3(0.3f, 0.4f, 0.5f);
  finalize_scene(*s);
  return s;
}

TEST(Instance, RendersTheSameImageAsTheFlattenedGeometry) {
  const auto inst = make(true, 12), flat = make(false, 12);
  EXPECT_EQ(represented_triangles(inst->geometry), represented_triangles(flat->geometry));
  const int w = 96, h = 72;
  const CameraBasis b = make_camera_basis(inst->camera, w, h);
  double sq = 0.0;
  int differ = 0, on_spheres = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const SampleResult a = trace_sample(*inst, b, float(x) + 0.5f, float(y) + 0.5f, 1);
      const SampleResult c = trace_sample(*flat, b, float(x) + 0.5f, float(y) + 0.5f, 1);
      ASSERT_TRUE(a.valid && c.valid);
      const Vec3 d = a.color - c.color;
      sq += double(glm::dot(d, d)) / 3.0;
      differ += glm::length(d) > 0.02f;
      Hit hit;
      on_spheres += scene_intersect(*inst, nullptr, camera_ray(b, float(x) + 0.5f, float(y) + 0.5f), hit) &&
                    hit.inst != kInvalidId;
    }
  const double rmse = std::sqrt(sq / double(w * h));
  // Tolerance: rays in instance space round differently, so a hit may move by an ulp-scale
  // distance (and a silhouette pixel may flip); no systematic difference is allowed.
  EXPECT_LT(rmse, 2e-3) << rmse;
  EXPECT_LE(differ, w * h / 200) << differ;
  EXPECT_GT(on_spheres, w * h / 4);
}

TEST(Instance, MirroredAndStretchedInstancesKeepTrueNormals) {
  const auto s = make(true, 12);
  // Rays at each instance's centre from several directions: the normal must be the ellipsoid's
  // analytic normal M^-T p_object at the hit, pointing outward and against the ray.
  int checked = 0;
  for (const Instance& inst : s->geometry.instances) {
    for (int k = 0; k < 6; ++k) {
      Ray r;
      const Vec3 centre = inst.to_world.t;
      const Vec3 dir = glm::normalize(Vec3(std::cos(1.1f * float(k)), -0.4f, std::sin(1.1f * float(k))));
      r.org = centre - 6.0f * dir;
      r.dir = dir;
      Hit hit;
      ASSERT_TRUE(scene_intersect(*s, nullptr, r, hit));
      if (hit.inst == kInvalidId) continue;  // another instance or the floor is in front
      const SurfacePoint sp = scene_surface_point(*s, nullptr, r, hit);
      const Instance& hi = s->accel.instance_top()->instances[hit.inst];
      const Vec3 po = hi.to_object.point(sp.p);
      // The flattened triangle's own normal: world vertices, winding flipped by a mirror.
      const Geometry& mg = s->geometry.instance_meshes[0]->geometry;
      const UVec3 t = mg.triangles[hit.prim];
      const Vec3 a = hi.to_world.point(mg.positions[t.x]), bb = hi.to_world.point(mg.positions[t.y]),
                 c = hi.to_world.point(mg.positions[t.z]);
      Vec3 expect = glm::normalize(glm::cross(bb - a, c - a));
      if (glm::determinant(hi.to_world.m) < 0.0f) expect = -expect;
      EXPECT_GT(glm::dot(sp.ns, expect), 0.9999f);               // the true normal
      EXPECT_GT(glm::dot(sp.ns, sp.p - hi.to_world.t), 0.0f);    // outward
      EXPECT_LT(glm::dot(sp.ng, r.dir), 0.0f);                   // faces the incoming ray
      EXPECT_TRUE(sp.front_face);                                // the outside was hit
      EXPECT_NEAR(glm::length(po), 1.0f, 0.02f);                 // on the (tessellated) sphere
      ++checked;
    }
  }
  EXPECT_GT(checked, 30);
}

TEST(Instance, PacketsMatchSingleRaysThroughInstances) {
  const auto s = make(true, 12);
  const CameraBasis b = make_camera_basis(s->camera, 64, 48);
  int hits = 0;
  for (int y = 0; y < 48; y += 2)
    for (int x = 0; x < 64; x += 4) {
      Ray rays[kPacketSize];
      for (int k = 0; k < kPacketSize; ++k)
        rays[k] = camera_ray(b, float(x + k % 4) + 0.5f, float(y + k / 4) + 0.5f);
      Hit packet[kPacketSize];
      s->accel.intersect_packet(rays, kPacketSize, packet);
      for (int k = 0; k < kPacketSize; ++k) {
        Hit single;
        const bool found = s->accel.intersect(rays[k], single);
        ASSERT_EQ(found, packet[k].valid());
        if (!found) continue;
        ASSERT_EQ(single.t, packet[k].t);
        ASSERT_EQ(single.prim, packet[k].prim);
        ASSERT_EQ(single.inst, packet[k].inst);
        hits += single.inst != kInvalidId;
      }
    }
  EXPECT_GT(hits, 100);
}

TEST(Instance, SingularTransformsAreRejected) {
  Affine a;
  a.m = glm::mat3(Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 1));  // rank 2
  Instance inst;
  EXPECT_FALSE(make_instance(0, a, inst));
  a.m = glm::mat3(1.0f);
  a.t = Vec3(kInfinity, 0, 0);
  EXPECT_FALSE(make_instance(0, a, inst));
}

// Cut-out leaves on instanced plants: shadow and camera rays pass where the leaf texture's
// alpha is 0, and the scene represents what it says.
TEST(Instance, SunflowerFieldInstancesCutOutLeaves) {
  auto s = make_sunflowers(40);
  ASSERT_TRUE(s) << s.error().message;
  const Scene& scene = **s;
  EXPECT_EQ(scene.geometry.instances.size(), 40u + 14u);
  EXPECT_GT(represented_triangles(scene.geometry), 40u * 10000u);
  // Through a leaf's cut-out corner (uv (0.02, 0.98) is outside the blade) rays hit nothing of it.
  const InstancedMesh& mesh = *scene.geometry.instance_meshes[0];
  int opaque = 0, clear = 0;
  for (uint32_t t = 0; t < mesh.geometry.num_triangles(); ++t) {
    if (mesh.geometry.triangle_material[t] != 1) continue;  // the leaf material
    const UVec3 tri = mesh.geometry.triangles[t];
    for (const float w : {0.05f, 0.33f}) {
      const Vec3 p = (1.0f - 2.0f * w) * mesh.geometry.positions[tri.x] +
                     w * mesh.geometry.positions[tri.y] + w * mesh.geometry.positions[tri.z];
      const Vec3 n = glm::normalize(glm::cross(mesh.geometry.positions[tri.y] - mesh.geometry.positions[tri.x],
                                               mesh.geometry.positions[tri.z] - mesh.geometry.positions[tri.x]));
      Ray r;
      r.org = p + 1e-3f * n;
      r.dir = -n;
      r.tmax = 2e-3f;
      Hit h;
      (mesh.accel.intersect(r, h) ? opaque : clear) += 1;
    }
  }
  EXPECT_GT(opaque, 0);
  EXPECT_GT(clear, 0);  // the cut-out removes parts of leaves
}

}  // namespace
}  // namespace frameless
