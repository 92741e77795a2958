// Ray packets against single rays: the same hit, distance, primitive and barycentrics bit for
// bit, and the same occlusion, for coherent camera packets, incoherent packets whose rays start
// inside the scene, partly filled packets, degenerate directions and cut-out surfaces.
#include <gtest/gtest.h>

#include <cstring>

#include "core/accel/accel.h"
#include "random_geometry.h"

#include "slow_build.h"

namespace frameless {
namespace {

#if defined(FRAMELESS_SLOW_BUILD)
constexpr int kPackets = 4000;
#else
constexpr int kPackets = 20000;  // 160,000 rays per scene and query
#endif

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Agreement {
  int rays = 0, hits = 0, occluded = 0;
};

// Traces n rays as a packet and one by one; asserts equality lane by lane.
void expect_packet_matches(const Accel& accel, const Ray* rays, int n, Agreement& a) {
  Hit packet[kPacketSize];
  bool occ[kPacketSize];
  for (Hit& h : packet) h = Hit{7.0f, 3u, 0.5f, 0.5f};  // stale contents must be reset
  accel.intersect_packet(rays, n, packet);
  accel.occluded_packet(rays, n, occ);
  for (int i = 0; i < n; ++i) {
    Hit single;
    const bool found = accel.intersect(rays[i], single);
    ASSERT_EQ(packet[i].valid(), found) << "ray " << a.rays;
    ASSERT_EQ(occ[i], accel.occluded(rays[i])) << "ray " << a.rays;
    if (found) {
      ASSERT_TRUE(same_bits(packet[i].t, single.t)) << packet[i].t << " vs " << single.t;
      ASSERT_EQ(packet[i].prim, single.prim) << "ray " << a.rays;
      ASSERT_TRUE(same_bits(packet[i].u, single.u) && same_bits(packet[i].v, single.v))
          << packet[i].u << " " << single.u << " " << packet[i].v << " " << single.v << " lane " << i
          << " of " << n << " t " << single.t;
      ++a.hits;
    }
    a.occluded += occ[i];
    ++a.rays;
  }
}

// Eight rays from one eye through a 4x2 block of pixels of a view of the unit cube.
void camera_packet(TestRng& rng, Ray* rays) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const Vec3 eye(2.5f, 1.9f, 3.1f), fwd = glm::normalize(-eye);
  const Vec3 right = glm::normalize(glm::cross(fwd, Vec3(0, 1, 0))), up = glm::cross(right, fwd);
  const float px = u(rng) * 510.0f, py = u(rng) * 510.0f;  // a 512x512 image, 45 degrees
  for (int k = 0; k < kPacketSize; ++k) {
    const float x = ((px + float(k % 4)) / 512.0f - 0.5f) * 0.83f;
    const float y = ((py + float(k / 4)) / 512.0f - 0.5f) * 0.83f;
    rays[k] = Ray{};
    rays[k].org = eye;
    rays[k].dir = glm::normalize(fwd + x * right + y * up);
  }
}

// Eight rays of one octant from anywhere in and around the scene: boxes entered from inside,
// a loose interval bound, some lanes with zero direction components, some with short intervals.
void scattered_packet(TestRng& rng, Ray* rays) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const Vec3 sign(u(rng) < 0.5f ? -1.0f : 1.0f, u(rng) < 0.5f ? -1.0f : 1.0f,
                  u(rng) < 0.5f ? -1.0f : 1.0f);
  const Vec3 base = uniform_vec(rng, -1.2f, 1.2f);
  const float spread = u(rng) < 0.5f ? 0.05f : 1.0f;
  for (int k = 0; k < kPacketSize; ++k) {
    Ray& r = rays[k];
    r = Ray{};
    r.org = base + spread * uniform_vec(rng, -1.0f, 1.0f);
    Vec3 d = sign * (Vec3(0.05f) + uniform_vec(rng, 0.0f, 1.0f));
    if (u(rng) < 0.15f) d[int(u(rng) * 2.999f)] = 0.0f * sign[0];  // +0 or -0 by the octant
    r.dir = glm::normalize(d);
    if (u(rng) < 0.2f) r.tmin = u(rng);
    if (u(rng) < 0.3f) r.tmax = r.tmin + 2.0f * u(rng);
  }
  // A zeroed component must carry the octant's sign bit, or the packet goes ray by ray.
  for (int k = 0; k < kPacketSize; ++k)
    for (int a = 0; a < 3; ++a)
      if (rays[k].dir[a] == 0.0f) rays[k].dir[a] = std::copysign(0.0f, sign[a]);
}

void run_packets(const Accel& accel, uint32_t seed, Agreement& a) {
  TestRng rng(seed);
  std::uniform_int_distribution<int> fill(1, kPacketSize);
  Ray rays[kPacketSize];
  for (int p = 0; p < kPackets; ++p) {
    if (p % 2 == 0)
      camera_packet(rng, rays);
    else
      scattered_packet(rng, rays);
    const int n = p % 5 == 0 ? fill(rng) : kPacketSize;  // partly active packets
    expect_packet_matches(accel, rays, n, a);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST(Packet, TrianglesMatchSingleRays) {
  Geometry g = random_triangles(11, 20000, true);
  Accel accel;
  accel.build(g);
  Agreement a;
  run_packets(accel, 5, a);
  // Not vacuous: many rays hit, and the scattered ones are often occluded.
  EXPECT_GT(a.hits, a.rays / 4);
  EXPECT_GT(a.occluded, a.rays / 4);
}

TEST(Packet, SpheresAndTrianglesMatchSingleRays) {
  Geometry g = mixed_scene(12, 20000);
  Accel accel;
  accel.build(g);
  Agreement a;
  run_packets(accel, 6, a);
  EXPECT_GT(a.hits, a.rays / 4);
}

TEST(Packet, SpheresOnlyMatchSingleRays) {
  Geometry g = random_spheres(13, 50000);
  Accel accel;
  accel.build(g);
  Agreement a;
  run_packets(accel, 7, a);
  EXPECT_GT(a.hits, a.rays / 4);
}

// Closely stacked coplanar copies: exact distance ties, decided by the lower primitive id.
TEST(Packet, ExactTiesResolveAlike) {
  Geometry g;
  for (int k = 0; k < 6; ++k)
    for (int i = 0; i < 200; ++i) {
      const float x = -1.0f + 0.01f * float(i);
      add_triangle(g, {x, -1, 0}, {x + 0.5f, -1, 0}, {x, 1, 0});
    }
  Accel accel;
  accel.build(g);
  TestRng rng(8);
  Ray rays[kPacketSize];
  Agreement a;
  for (int p = 0; p < kPackets / 10; ++p) {
    camera_packet(rng, rays);
    for (Ray& r : rays)
      r.org = Vec3(0.3f, 0.2f, 3.0f), r.dir = glm::normalize(Vec3(0.25f * r.dir.x, 0.25f * r.dir.y, -1.0f));
    expect_packet_matches(accel, rays, kPacketSize, a);
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(a.hits, a.rays / 2);
}

// Cut-out surfaces: the alpha callback decides per candidate in packets too.
TEST(Packet, CutOutsMatchSingleRays) {
  Geometry g = random_triangles(14, 20000, false);
  std::vector<uint8_t> masked(g.num_triangles(), 0);
  for (size_t i = 0; i < masked.size(); i += 2) masked[i] = 1;  // every other material
  Accel accel;
  accel.build(g);
  Accel::AlphaTest alpha;
  alpha.masked_material = masked.data();
  alpha.opaque = [](const void*, uint32_t, const Ray&, float, float u, float v) {
    return u + v > 0.4f;  // a hole near vertex 0
  };
  accel.set_alpha_test(alpha);
  Agreement a;
  run_packets(accel, 9, a);
  EXPECT_GT(a.hits, a.rays / 4);
}

}  // namespace
}  // namespace frameless
