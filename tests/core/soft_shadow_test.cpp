// Single-sample soft shadows (seed section 3.2): penumbra geometry, exact 0 and 1, no leaks,
// accuracy against the area-sampled reference, transparent shadows, directional lights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"
#include "core/shading/render_sample.h"
#include "core/shading/soft_shadow.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

using testing::add_horizontal_quad;
using testing::make_empty_scene;

// Shadow query from p toward a spherical light (centre c, radius r), as shading makes it.
ShadowQuery query_to(const Vec3& p, const Vec3& c, float r) {
  ShadowQuery q;
  q.org = p;
  const Vec3 d = c - p;
  const float dist = glm::length(d);
  q.dir = d / dist;
  q.tmax = (dist - r) * (1.0f - 0x1.0p-12f);
  q.half_angle = std::asin(r / dist);
  q.tan_half = r / std::sqrt((dist - r) * (dist + r));
  return q;
}

// A half-plane occluder: a large thin plate covering x < 0 at height 0 (a closed box, so its
// edges are real silhouettes), lit from a light of radius R at height L above the plate's edge.
std::unique_ptr<Scene> edge_scene() {
  auto s = make_empty_scene();
  s->materials.push_back(Material{});
  add_box(*s, Vec3(-50.0f, -0.01f, -50.0f), Vec3(0.0f, 0.0f, 50.0f), 0);
  s->lights.push_back(Light{Vec3(0.0f, 10.0f, 0.0f), Vec3(1.0f), 1.0f});
  finalize_scene(*s);
  return s;
}

// x where the visibility on the receiver plane y = -h crosses `level` (bisection; s grows with x).
float crossing(const Scene& s, float h, float level) {
  float lo = -20.0f, hi = 20.0f;
  for (int i = 0; i < 60; ++i) {
    const float mid = 0.5f * (lo + hi);
    const float v = soft_visibility(s, query_to(Vec3(mid, -h, 0.0f), Vec3(0, 10, 0), 1.0f));
    (v < level ? lo : hi) = mid;
  }
  return 0.5f * (lo + hi);
}

TEST(SoftShadow, EdgeVisibilityIsTheDiskFractionBehindAStraightEdge) {
  EXPECT_EQ(edge_visibility(-1.0f), 0.0f);
  EXPECT_EQ(edge_visibility(1.0f), 1.0f);
  EXPECT_NEAR(edge_visibility(0.0f), 0.5f, 1e-6f);
  // Symmetry: what one side loses the other gains.
  for (float x : {0.1f, 0.37f, 0.8f}) EXPECT_NEAR(edge_visibility(x) + edge_visibility(-x), 1.0f, 1e-5f);
  // A chord at half the radius leaves the segment area (pi/3 - sqrt(3)/4)/pi covered.
  EXPECT_NEAR(edge_visibility(0.5f), 1.0f - (kPi / 3.0f - std::sqrt(3.0f) / 4.0f) / kPi, 1e-5f);
}

TEST(SoftShadow, PenumbraWidthGrowsLinearlyWithReceiverDistance) {
  auto s = edge_scene();
  // The light is fixed 10 above the occluder; the receiver moves to 1, 2, 4 and 8 below it.
  float widths[4];
  const float hs[4] = {1.0f, 2.0f, 4.0f, 8.0f};
  for (int i = 0; i < 4; ++i) {
    widths[i] = crossing(*s, hs[i], 0.95f) - crossing(*s, hs[i], 0.05f);
    // The hard shadow's edge (x = 0) lies inside the penumbra: it straddles the edge.
    EXPECT_LT(crossing(*s, hs[i], 0.05f), 0.0f);
    EXPECT_GT(crossing(*s, hs[i], 0.95f), 0.0f);
    EXPECT_NEAR(crossing(*s, hs[i], 0.5f), 0.0f, 0.02f * widths[i]);
  }
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(widths[i] / widths[0], hs[i] / hs[0], 0.03f * hs[i]);
  // Similar triangles: an area light of radius R at height L gives a full width 2 R h / L; the
  // 5-95 % band of the disk's edge profile is 0.84 of it.
  const float full = 2.0f * 1.0f * 8.0f / 10.0f;
  EXPECT_NEAR(widths[3] / full, 0.845f, 0.05f);
}

TEST(SoftShadow, InnerObjectGivesZeroAndClearingTheOuterGivesOneExactly) {
  auto s = make_empty_scene();
  s->materials.push_back(Material{});
  testing::add_sphere(s->geometry, Vec3(0.0f, 5.0f, 0.0f), 1.0f, 0);
  add_horizontal_quad(s->geometry, 0.0f, 20.0f, 0);
  s->lights.push_back(Light{Vec3(0.0f, 10.0f, 0.0f), Vec3(1.0f), 0.5f});
  finalize_scene(*s);
  // Straight under the centre: the ray crosses the inner (shrunk) sphere.
  EXPECT_EQ(soft_visibility(*s, query_to(Vec3(0, 0.001f, 0), Vec3(0, 10, 0), 0.5f)), 0.0f);
  // Far to the side: the ray clears every outer shell.
  EXPECT_EQ(soft_visibility(*s, query_to(Vec3(6, 0.001f, 0), Vec3(0, 10, 0), 0.5f)), 1.0f);
  // Just outside the hard shadow's edge (x = 2.05 on the plane, where the ray to the light's
  // centre grazes the sphere): partly lit, more than half.
  const float edge = soft_visibility(*s, query_to(Vec3(2.1f, 0.001f, 0), Vec3(0, 10, 0), 0.5f));
  EXPECT_GT(edge, 0.5f);
  EXPECT_LT(edge, 1.0f);
  // A triangle occluder behaves the same way: deep inside its shadow exactly 0.
  auto e = edge_scene();
  EXPECT_EQ(soft_visibility(*e, query_to(Vec3(-5, -1, 0), Vec3(0, 10, 0), 1.0f)), 0.0f);
  EXPECT_EQ(soft_visibility(*e, query_to(Vec3(5, -1, 0), Vec3(0, 10, 0), 1.0f)), 1.0f);
}

// Parker's beam shadows: four fixed rays across the light, one packet. Under the half-plane's
// edge the visibility steps 0, 1/2, 1 as the point moves out (the four rays split two and two
// between the plate and the sky), the packet answers as the rays do one by one, and where the
// area reference is deep in shadow or fully lit the beam agrees exactly.
TEST(SoftShadow, BeamShadowsStepInQuartersAndMatchSingleRays) {
  auto s = edge_scene();
  EXPECT_EQ(beam_visibility(*s, query_to(Vec3(-5, -1, 0), Vec3(0, 10, 0), 1.0f)).x, 0.0f);
  EXPECT_EQ(beam_visibility(*s, query_to(Vec3(5, -1, 0), Vec3(0, 10, 0), 1.0f)).x, 1.0f);
  EXPECT_EQ(beam_visibility(*s, query_to(Vec3(0, -1, 0), Vec3(0, 10, 0), 1.0f)).x, 0.5f);
  float last = 0.0f;
  for (int i = 0; i <= 80; ++i) {
    const float x = -2.0f + 0.05f * float(i);
    const ShadowQuery q = query_to(Vec3(x, -4.0f, 0.3f), Vec3(0, 10, 0), 1.0f);
    const float v = beam_visibility(*s, q).x;
    EXPECT_EQ(v * 4.0f, std::round(v * 4.0f)) << x;  // quarters only
    EXPECT_GE(v, last) << x;                          // never darker further out
    last = v;
    // Ray by ray (the path with a moving-object frame) gives the same answer as the packet.
    const DynamicFrame frame;
    EXPECT_EQ(beam_visibility(*s, q, &frame).x, v) << x;
  }
  EXPECT_EQ(last, 1.0f);
}

TEST(SoftShadow, TouchingOccludersLeakNoLight) {
  auto s = make_empty_scene();
  s->materials.push_back(Material{});
  // Two boxes side by side sharing the plane x = 0, over a receiver.
  add_box(*s, Vec3(-3.0f, 2.0f, -3.0f), Vec3(0.0f, 3.0f, 3.0f), 0);
  add_box(*s, Vec3(0.0f, 2.0f, -3.0f), Vec3(3.0f, 3.0f, 3.0f), 0);
  s->lights.push_back(Light{Vec3(0.0f, 10.0f, 0.0f), Vec3(1.0f), 1.5f});
  finalize_scene(*s);
  // Under the seam and near it, each box alone would leave half the light showing.
  for (float x : {0.0f, 0.05f, -0.05f, 0.2f, -0.3f})
    EXPECT_EQ(soft_visibility(*s, query_to(Vec3(x, 0.0f, 0.5f), Vec3(0, 10, 0), 1.5f)), 0.0f)
        << "x = " << x;
  // The outer edges of the pair still have a penumbra: the hard shadow of the top corner
  // (3, 3) from the light's centre ends at x = 30/7.
  const float outer = soft_visibility(*s, query_to(Vec3(30.0f / 7.0f, 0.0f, 0.0f), Vec3(0, 10, 0), 1.5f));
  EXPECT_GT(outer, 0.2f);
  EXPECT_LT(outer, 0.8f);
}

TEST(SoftShadow, MeshInteriorEdgesAreNotOutlines) {
  // A finely tessellated plate (many small triangles): inside its shadow s stays 0 even where the
  // ray passes right next to interior edges.
  auto s = make_empty_scene();
  s->materials.push_back(Material{});
  MeshData m;
  const int n = 40;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.positions.push_back(Vec3(-4.0f + 8.0f * float(i) / n, 3.0f, -4.0f + 8.0f * float(j) / n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n) + 1, d = c + 1;
      m.triangles.push_back(UVec3(a, c, b));
      m.triangles.push_back(UVec3(b, c, d));
    }
  add_mesh(*s, m, glm::mat4(1.0f), 0);
  s->lights.push_back(Light{Vec3(0.0f, 10.0f, 0.0f), Vec3(1.0f), 1.0f});
  finalize_scene(*s);
  for (float x : {0.0f, 0.1f, 0.2f, 1.0f, -1.5f})
    EXPECT_EQ(soft_visibility(*s, query_to(Vec3(x, 0.0f, 0.03f), Vec3(0, 10, 0), 1.0f)), 0.0f);
  // Near the plate's border the penumbra is there, centred on the hard edge.
  const float border = soft_visibility(*s, query_to(Vec3(4.0f * 10.0f / 7.0f, 0.0f, 0.0f),
                                                    Vec3(0, 10, 0), 1.0f));
  EXPECT_NEAR(border, 0.5f, 0.1f);
}

// Mean squared difference of two renders of the same scene at 96x72, 4 samples per pixel.
double rmse(const Scene& a, const Scene& b) {
  const int w = 96, h = 72;
  const CameraBasis cam = make_camera_basis(a.camera, w, h);
  double sum = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Vec3 ca(0.0f), cb(0.0f);
      for (uint32_t k = 0; k < 4; ++k) {
        ca += render_sample(a, cam, x, y, k).color;
        cb += render_sample(b, cam, x, y, k).color;
      }
      const Vec3 d = (ca - cb) * 0.25f;
      sum += double(glm::dot(d, d)) / 3.0;
    }
  return std::sqrt(sum / (w * h));
}

TEST(SoftShadow, CloserToTheAreaReferenceThanHardShadows) {
  auto load = [](ShadowMode mode) {
    auto s = load_scene(std::string(FRAMELESS_TEST_DATA) + "/scenes/soft_shadows.json");
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    set_shadow_settings(*s.value(), mode, 256, false);
    return std::move(s.value());
  };
  auto soft = load(ShadowMode::kSoft), hard = load(ShadowMode::kHard), area = load(ShadowMode::kArea);
  const double e_soft = rmse(*soft, *area), e_hard = rmse(*hard, *area);
  std::printf("soft-shadow test scene: RMSE against area reference: soft %.4f, hard %.4f\n", e_soft,
              e_hard);
  EXPECT_LT(e_soft, 0.6 * e_hard);
}

TEST(SoftShadow, TransparentShadowsThroughGlass) {
  auto s = make_empty_scene();
  Material glass;
  glass.cls = MaterialClass::kDielectric;
  glass.ior = 1.5f;
  glass.extinction = Vec3(0.0f, 0.5f, 1.0f);
  s->materials.push_back(glass);
  testing::add_sphere(s->geometry, Vec3(0.0f, 5.0f, 0.0f), 1.0f, 0);
  finalize_scene(*s);
  Ray r;
  r.org = Vec3(0.0f);
  r.dir = Vec3(0.0f, 1.0f, 0.0f);
  r.tmax = 10.0f;
  // Through the centre: k_t = 1 - R0 twice, and exp(-kappa 2r) inside.
  const float kt = 1.0f - 0.04f;
  const Vec3 t = shadow_transmittance(*s, r, false);
  EXPECT_NEAR(t.x, kt * kt, 1e-3f);
  EXPECT_NEAR(t.y, kt * kt * std::exp(-1.0f), 1e-3f);
  EXPECT_NEAR(t.z, kt * kt * std::exp(-2.0f), 1e-3f);
  // An opaque occluder still blocks.
  s->materials[0].cls = MaterialClass::kDiffuse;
  EXPECT_EQ(shadow_transmittance(*s, r, false), Vec3(0.0f));
  EXPECT_EQ(shadow_transmittance(*s, r, true), Vec3(1.0f));
}

TEST(SoftShadow, DirectionalLightCastsSunShadows) {
  auto s = make_empty_scene();
  s->materials.push_back(Material{});
  s->materials[0].kd = Vec3(1.0f);
  add_horizontal_quad(s->geometry, 0.0f, 50.0f, 0);
  add_box(*s, Vec3(-1.0f, 2.0f, -1.0f), Vec3(1.0f, 3.0f, 1.0f), 0);
  Light sun;
  sun.kind = LightKind::kDirectional;
  sun.direction = Vec3(0.0f, -1.0f, 0.0f);
  sun.angular_radius = glm::radians(5.0f);
  s->lights.push_back(sun);
  finalize_scene(*s);
  s->camera.eye = Vec3(0.0f, 20.0f, 0.01f);
  s->camera.look = Vec3(0.0f);
  s->camera.fov_deg = 30.0f;
  const CameraBasis cam = make_camera_basis(s->camera, 65, 65);
  // A corner of the image sees the ground in full sun: k_d l_e n.l = 1.
  const Vec3 corner = render_sample(*s, cam, 2, 2, 0, false).color;
  EXPECT_NEAR(corner.x, 1.0f, 1e-4f);
  ShadowQuery q;
  q.org = Vec3(0.0f, 0.001f, 0.0f);
  q.dir = Vec3(0.0f, 1.0f, 0.0f);
  q.half_angle = sun.angular_radius;
  q.tan_half = std::tan(q.half_angle);
  EXPECT_EQ(soft_visibility(*s, q), 0.0f);
  // Under the box's vertical side (x = 1) the sun is half hidden; outside, the top edge (3 above
  // the ground) is the outline, so the sun is whole from 3 tan(5 deg) beyond the side.
  q.org.x = 1.0f;
  EXPECT_NEAR(soft_visibility(*s, q), 0.5f, 0.05f);
  q.org.x = 1.0f + 3.0f * std::tan(q.half_angle) + 0.01f;
  EXPECT_EQ(soft_visibility(*s, q), 1.0f);
  q.org.x = 1.0f + 1.5f * std::tan(q.half_angle);
  EXPECT_GT(soft_visibility(*s, q), 0.5f);
  EXPECT_LT(soft_visibility(*s, q), 1.0f);
}

TEST(SoftShadow, ObliqueSunOverAPartlyFilledBvh) {
  // BVH nodes with empty slots and a sun whose direction has no zero component: the cone's box
  // test must skip the empty slots even though its growth is unbounded (tmax is infinite).
  auto s = testing::make_empty_scene();
  s->materials.push_back(Material{});
  add_horizontal_quad(s->geometry, 0.0f, 20.0f, 0);
  for (int i = 0; i < 5; ++i) testing::add_sphere(s->geometry, Vec3(float(i) * 2.5f - 5.0f, 1.5f, 0.0f), 0.8f, 0);
  Light sun;
  sun.kind = LightKind::kDirectional;
  sun.direction = glm::normalize(Vec3(-0.3f, -1.0f, -0.2f));
  sun.angular_radius = glm::radians(3.0f);
  s->lights.push_back(sun);
  finalize_scene(*s);
  ShadowQuery q;
  q.dir = -sun.direction;
  q.half_angle = sun.angular_radius;
  q.tan_half = std::tan(q.half_angle);
  int dark = 0, lit = 0;
  for (int i = 0; i < 200; ++i) {
    q.org = Vec3(-8.0f + 0.08f * float(i), 0.001f, 0.1f);
    const float v = soft_visibility(*s, q);
    ASSERT_GE(v, 0.0f);
    ASSERT_LE(v, 1.0f);
    dark += v == 0.0f;
    lit += v == 1.0f;
  }
  // The spheres' shadows fall on this line (offset along the sun's slant), with lit ground between.
  EXPECT_GT(dark, 10);
  EXPECT_GT(lit, 10);
}

TEST(SoftShadow, LightInsideASphereStillLightsItsInside) {
  // A dome: a big sphere seen from inside with the light inside it too.
  auto s = testing::make_empty_scene();
  s->materials.push_back(Material{});
  testing::add_sphere(s->geometry, Vec3(0.0f), 10.0f, 0);
  finalize_scene(*s);
  // From a point on the inner surface toward a light of radius 1 at the centre.
  EXPECT_EQ(soft_visibility(*s, query_to(Vec3(0.0f, -9.99f, 0.0f), Vec3(0.0f), 1.0f)), 1.0f);
  // From outside the sphere the same light is hidden.
  EXPECT_EQ(soft_visibility(*s, query_to(Vec3(0.0f, -12.0f, 0.0f), Vec3(0.0f), 1.0f)), 0.0f);
}

TEST(SoftShadow, TransmittanceFromInsideGlass) {
  auto s = testing::make_empty_scene();
  Material glass;
  glass.cls = MaterialClass::kDielectric;
  glass.extinction = Vec3(1.0f);
  s->materials.push_back(glass);
  testing::add_sphere(s->geometry, Vec3(0.0f), 2.0f, 0);
  finalize_scene(*s);
  // Starting at the centre, leaving once: Beer's law over the radius, one interface.
  Ray r;
  r.org = Vec3(0.0f);
  r.dir = Vec3(0, 1, 0);
  r.tmax = 10.0f;
  const float kt = 1.0f - 0.04f;
  EXPECT_NEAR(shadow_transmittance(*s, r, false).x, kt * std::exp(-2.0f), 1e-3f);
  // From outside to a light inside the glass: one interface, absorption up to the light.
  r.org = Vec3(0.0f, -5.0f, 0.0f);
  r.tmax = 4.0f;  // ends at y = -1, one unit inside
  EXPECT_NEAR(shadow_transmittance(*s, r, false).x, kt * std::exp(-1.0f), 1e-3f);
}

}  // namespace
}  // namespace frameless
