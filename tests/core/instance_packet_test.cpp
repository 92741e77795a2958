// Packets through instances (core/accel/instance_packet.cpp): rays that walk the top level
// together give the single-ray answers bit for bit, on a field of cut-out plants, with exact ties
// between coincident instances and flat geometry, with no flat geometry at all, and for
// incoherent rays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/accel/instance.h"
#include "core/accel/instance_top.h"
#include "core/base/rng.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/builtin_scenes.h"

namespace frameless {
namespace {

// A closed box mesh [-1, 1]^3 (twelve triangles).
Geometry packet_box_mesh(uint16_t material) {
  Geometry g;
  for (int i = 0; i < 8; ++i) g.positions.push_back(Vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  const uint32_t quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : quads) {
    g.triangles.push_back({q[0], q[1], q[2]});
    g.triangles.push_back({q[0], q[2], q[3]});
  }
  g.triangle_material.assign(g.triangles.size(), material);
  return g;
}

// Rows of boxes as instances; `coincident`: the first placement twice more as instances (exact
// ties: the lower instance wins) and the second once more as flat triangles (flat geometry wins
// what ties); `floor`: a quad.
std::unique_ptr<Scene> packet_box_field(bool coincident, bool floor) {
  auto s = std::make_unique<Scene>();
  const uint16_t grey = add_material(*s, diffuse("grey", Vec3(0.6f)));
  if (floor) add_quad(*s, Vec3(0, -1, -6), Vec3(0, 1, 0), 40.0f, grey);
  auto mesh = std::make_shared<InstancedMesh>();
  mesh->geometry = packet_box_mesh(grey);
  build_instanced_mesh(*mesh);
  std::vector<Affine> placements;
  for (int k = 0; k < 24; ++k) {
    Affine a;
    const float c = std::cos(0.5f * float(k)), sn = std::sin(0.5f * float(k));
    a.m = glm::mat3(Vec3(c, 0, -sn), Vec3(0, 1, 0), Vec3(sn, 0, c)) *
          glm::mat3(Vec3(0.5f + 0.05f * float(k % 5), 0, 0), Vec3(0, 0.4f + 0.1f * float(k % 3), 0), Vec3(0, 0, 0.6f));
    a.t = Vec3(1.7f * float(k % 6) - 4.5f, 0.0f, -2.2f * float(k / 6));
    placements.push_back(a);
  }
  if (coincident) {
    placements.insert(placements.begin() + 5, placements[0]);
    placements.push_back(placements[0]);
    Geometry& g = s->geometry;
    const uint32_t base = uint32_t(g.positions.size());  // after the floor's corners
    for (const Vec3& p : mesh->geometry.positions) g.positions.push_back(placements[1].point(p));
    for (const UVec3& t : mesh->geometry.triangles) g.triangles.push_back(t + base);
    g.triangle_material.insert(g.triangle_material.end(), mesh->geometry.triangles.size(), grey);
  }
  for (const Affine& a : placements) {
    Instance inst;
    EXPECT_TRUE(make_instance(0, a, inst));
    s->geometry.instances.push_back(inst);
  }
  s->geometry.instance_meshes.push_back(mesh);
  s->lights.push_back(Light{Vec3(3, 9, 6), Vec3(0.9f), 0.0f});
  s->camera.eye = Vec3(-1, 4, 6);
  s->camera.look = Vec3(0, 0, -3);
  finalize_scene(*s);
  return s;
}

struct PacketCounts {
  int instance_hits = 0, flat_hits = 0, blocked = 0, open = 0;
};

// Camera rays in 4x2 packets over a w x h image, then shadow rays from the light to each hit (one
// origin: coherent), through the Accel's packet queries, each checked against single rays.
PacketCounts check_packets(const Scene& s, int w, int h, const Vec3& light) {
  PacketCounts c;
  const CameraBasis b = make_camera_basis(s.camera, w, h);
  for (int y = 0; y < h; y += 2)
    for (int x = 0; x < w; x += 4) {
      Ray rays[kPacketSize], shadows[kPacketSize];
      for (int k = 0; k < kPacketSize; ++k) rays[k] = camera_ray(b, float(x + k % 4) + 0.5f, float(y + k / 4) + 0.5f);
      Hit packet[kPacketSize];
      s.accel.intersect_packet(rays, kPacketSize, packet);
      for (int k = 0; k < kPacketSize; ++k) {
        Hit single;
        const bool found = s.accel.intersect(rays[k], single);
        EXPECT_EQ(found, packet[k].valid()) << x << "," << y << " ray " << k;
        if (found) {
          EXPECT_EQ(single.t, packet[k].t);
          EXPECT_EQ(single.u, packet[k].u);
          EXPECT_EQ(single.v, packet[k].v);
          EXPECT_EQ(single.prim, packet[k].prim);
          EXPECT_EQ(single.inst, packet[k].inst) << x << "," << y << " ray " << k;
          (single.inst == kInvalidId ? c.flat_hits : c.instance_hits) += 1;
        }
        const Vec3 p = rays[k].org + (found ? single.t : 30.0f) * rays[k].dir;
        shadows[k].org = light;
        shadows[k].dir = p - light;
        shadows[k].tmin = 0.0f;
        shadows[k].tmax = 0.999f;
      }
      bool blocked[kPacketSize];
      s.accel.occluded_packet(shadows, kPacketSize, blocked);
      for (int k = 0; k < kPacketSize; ++k) {
        EXPECT_EQ(s.accel.occluded(shadows[k]), blocked[k]) << x << "," << y << " shadow " << k;
        (blocked[k] ? c.blocked : c.open) += 1;
      }
    }
  return c;
}

TEST(InstancePacket, CutOutPlantsMatchSingleRays) {
  auto s = make_sunflowers(64);
  ASSERT_TRUE(s) << s.error().message;
  const PacketCounts c = check_packets(**s, 96, 64, Vec3(20, 40, 30));
  EXPECT_GT(c.instance_hits, 1000);  // the plants fill most of the view
  EXPECT_GT(c.blocked, 200);         // and shade one another
  EXPECT_GT(c.open, 200);
}

TEST(InstancePacket, ExactTiesResolveAsSingleRaysDo) {
  const auto s = packet_box_field(true, true);
  const PacketCounts c = check_packets(*s, 128, 96, Vec3(3, 9, 6));
  EXPECT_GT(c.instance_hits, 1000);
  EXPECT_GT(c.flat_hits, 500);  // the floor and the flat copy, which wins its ties
  EXPECT_GT(c.blocked, 100);
  // The three coincident instances (declared 0, 5 and 25) tie exactly (the same object-space
  // rays): the one first in the top level's order shows, whatever order a walk meets them in.
  const auto& top = *s->accel.instance_top();
  const uint32_t first = std::min({top.position[0], top.position[5], top.position[25]});
  const CameraBasis b = make_camera_basis(s->camera, 128, 96);
  int tied = 0;
  for (int y = 0; y < 96; y += 2)
    for (int x = 0; x < 128; x += 4) {
      Ray rays[kPacketSize];
      for (int k = 0; k < kPacketSize; ++k) rays[k] = camera_ray(b, float(x + k % 4) + 0.5f, float(y + k / 4) + 0.5f);
      Hit packet[kPacketSize];
      s->accel.intersect_packet(rays, kPacketSize, packet);
      for (const Hit& h : packet) {
        if (h.inst == kInvalidId) continue;
        const uint32_t d = top.declared[h.inst];
        if (d != 0 && d != 5 && d != 25) continue;
        EXPECT_EQ(h.inst, first) << d;
        ++tied;
      }
    }
  EXPECT_GT(tied, 20);
}

TEST(InstancePacket, InstancesWithoutFlatGeometry) {
  const auto s = packet_box_field(false, false);
  ASSERT_EQ(s->geometry.num_triangles(), 0u);
  const PacketCounts c = check_packets(*s, 128, 96, Vec3(3, 9, 6));
  EXPECT_GT(c.instance_hits, 1000);
  EXPECT_GT(c.blocked, 100);
  EXPECT_EQ(c.flat_hits, 0);
}

// The top level's packet walk itself, with rays that share nothing (random origins, directions
// and interval ends): what each ray finds equals intersect_instances / occluded_instances, and
// the Accel's packet queries equal its single-ray ones.
TEST(InstancePacket, IncoherentRaysWalkTheTopLevelAlike) {
  const auto s = packet_box_field(true, true);
  const InstanceTop& top = *s->accel.instance_top();
  Rng rng(2026);
  int hits = 0, blocked = 0;
  for (int round = 0; round < 400; ++round) {
    Ray rays[kPacketSize];
    Hit packet[kPacketSize], single[kPacketSize];
    bool occluded[kPacketSize];
    const int n = 1 + round % kPacketSize;
    for (int k = 0; k < n; ++k) {
      rays[k].org = Vec3(12.0f * rng.next_float() - 6.0f, 4.0f * rng.next_float() - 1.0f, 2.0f - 14.0f * rng.next_float());
      rays[k].dir = glm::normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
      rays[k].tmin = 0.0f;
      rays[k].tmax = round % 3 == 0 ? kInfinity : 8.0f * rng.next_float();
      packet[k] = single[k] = Hit{};
      occluded[k] = round % 5 == 0 && k == 0;  // a ray already blocked stays so
    }
    intersect_instances_packet(top, rays, n, packet);
    occluded_instances_packet(top, rays, n, occluded);
    // Through the Accel: such packets fail the packet walk's coherence test, so the flat
    // geometry goes ray by ray and the instances' top level is walked together.
    Hit whole[kPacketSize];
    bool shadowed[kPacketSize];
    s->accel.intersect_packet(rays, n, whole);
    s->accel.occluded_packet(rays, n, shadowed);
    for (int k = 0; k < n; ++k) {
      Hit one;
      const bool found = s->accel.intersect(rays[k], one);
      ASSERT_EQ(found, whole[k].valid()) << round << " " << k;
      if (found) EXPECT_TRUE(one.t == whole[k].t && one.prim == whole[k].prim && one.inst == whole[k].inst);
      EXPECT_EQ(s->accel.occluded(rays[k]), shadowed[k]) << round << " " << k;
    }
    for (int k = 0; k < n; ++k) {
      const bool found = intersect_instances(top, rays[k], single[k], false);
      ASSERT_EQ(found, packet[k].valid()) << round << " " << k;
      if (found) {
        EXPECT_EQ(single[k].t, packet[k].t);
        EXPECT_EQ(single[k].prim, packet[k].prim);
        EXPECT_EQ(single[k].inst, packet[k].inst);
        ++hits;
      }
      const bool expect = (round % 5 == 0 && k == 0) || occluded_instances(top, rays[k]);
      EXPECT_EQ(expect, occluded[k]) << round << " " << k;
      blocked += occluded[k];
    }
  }
  EXPECT_GT(hits, 200);
  EXPECT_GT(blocked, 200);
}

}  // namespace
}  // namespace frameless
