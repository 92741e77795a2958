// Reprojection (the render cache): synthetic depth images under known camera moves land where the
// projection says (exactly, for a plane), uncovered pixels are marked and filled from behind, the
// row and vector searches match the window and scalar ones, the CPU budget spaces reprojections,
// and points are read whole (the display thread's use of it: reproject_display_test.cpp).
#include "display/reproject.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/scenes/scene_load.h"
#include "display/display_thread.h"
#include "frameless/engine.h"
#include "frameless/partition.h"
#include "reproject_cameras.h"

namespace frameless {
namespace {

constexpr int kW = 64, kH = 48;

// A synthetic frame seen from one camera: each pixel's centre ray hits the nearest of a
// background plane z = 0 and (optionally) a square at z = 2 with |x|, |y| < 0.5.
// The display keeps points relative to its camera (view_point.h): `world` holds them in world
// space for the test to shape, encode() writes what the display keeps, point() reads it back.
struct Synthetic {
  std::vector<DisplayPixel> px;
  std::vector<ScenePoint> world;
  std::vector<ViewPoint> points;
  std::vector<uint8_t> marks;
  CameraBasis camera;
  SlotImage image() {
    return {kW, kH, nullptr, nullptr, px.data(), points.data(), marks.data()};
  }
  Synthetic& encode() {
    points = encode_points(camera, world);
    return *this;
  }
  ScenePoint point(size_t t) const { return from_view(camera, points[t], t); }
  // encode_points: each world point kept by the pixel it projects into (none where that is
  // another pixel; the tests' points lie on their pixel's centre ray).
  static std::vector<ViewPoint> encode_points(const CameraBasis& b, const std::vector<ScenePoint>& world) {
    std::vector<ViewPoint> out(world.size());
    for (size_t i = 0; i < world.size(); ++i) {
      size_t at = i;
      const ViewPoint v = to_view(b, world[i], at);
      if (at == i) out[i] = v;
    }
    return out;
  }
};

// Nearest hit of a camera's centre ray through (px, py): the point and whether it is the square.
ScenePoint hit(const CameraBasis& b, float px, float py, bool square, bool* on_square = nullptr) {
  const Ray r = camera_ray(b, px, py);
  if (square) {
    const float t = (2.0f - r.org.z) / r.dir.z;
    const Vec3 q = r.org + t * r.dir;
    if (t > 0 && std::fabs(q.x) < 0.5f && std::fabs(q.y) < 0.5f) {
      if (on_square) *on_square = true;
      return {q, kPointStatic};
    }
  }
  if (on_square) *on_square = false;
  const float t = -r.org.z / r.dir.z;
  return {r.org + t * r.dir, kPointStatic};
}

// Colour encodes where the content came from: (x, y) of its pixel, blue 1 on the background.
Synthetic render(const CameraBasis& b, bool square) {
  Synthetic s;
  s.px.resize(size_t(kW) * kH);
  s.world.resize(s.px.size());
  s.camera = b;
  s.marks.assign(s.px.size(), kMarkNone);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const size_t i = size_t(y) * kW + size_t(x);
      bool sq = false;
      s.world[i] = hit(b, float(x) + 0.5f, float(y) + 0.5f, square, &sq);
      s.px[i].rgb[0] = float(x);
      s.px[i].rgb[1] = float(y);
      s.px[i].rgb[2] = sq ? 0.0f : 1.0f;
      s.px[i].epoch = 1 + uint32_t(i % 7);
    }
  s.encode();
  return s;
}

// Where camera b sees point q, across and down (in pixels).
float sx_of(const CameraBasis& b, const ScenePoint& q) {
  float x = -1e9f, y, d;
  project_point(b, q, x, y, d);
  return x;
}
float sy_of(const CameraBasis& b, const ScenePoint& q) {
  float x, y = -1e9f, d;
  project_point(b, q, x, y, d);
  return y;
}

CameraBasis basis(Vec3 eye, Vec3 look) { return look_at_basis(eye, look, kW, kH); }

TEST(Reproject, PlanePixelsLandWhereTheProjectionSays) {
  const CameraBasis a = basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f});
  const CameraBasis b = basis({0.3f, 0.2f, 4.6f}, {0.1f, 0.05f, 0.0f});
  Synthetic from = render(a, false), to = render(a, false);
  Reprojector r;
  const ReprojectStats st = r.run(a, b, from.image(), to.image());
  to.camera = b;  // the moved points are relative to the new camera
  EXPECT_GT(st.moved, size_t(kW * kH) * 8 / 10);
  size_t cracks = 0, crack_marked_uncovered = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const size_t t = size_t(y) * kW + size_t(x);
      const ScenePoint p = to.point(t);
      // Moved content keeps the point it was rendered with (to the 1/32768 pixel the display
      // keeps); a copy of a neighbour's content gets a point of its own, on its centre ray at
      // that neighbour's depth.
      const size_t src = size_t(to.px[t].rgb[1]) * kW + size_t(to.px[t].rgb[0]);
      const ScenePoint& q = from.world[src];
      if (to.marks[t] == kMarkMoved) {
        EXPECT_EQ(p.object, q.object);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(p.p[c], q.p[c], 2e-5f * glm::length(q.p - b.eye)) << x << "," << y;
      } else {
        float cx, cy, cd, sx, sy, sd;
        ASSERT_TRUE(project_point(b, p, cx, cy, cd));
        ASSERT_TRUE(project_point(b, q, sx, sy, sd));
        EXPECT_NEAR(cx, float(x) + 0.5f, 1e-3f) << x << "," << y;
        EXPECT_NEAR(cy, float(y) + 0.5f, 1e-3f) << x << "," << y;
        EXPECT_NEAR(cd, sd, 1e-5f * sd) << x << "," << y;
      }
      EXPECT_EQ(to.px[t].epoch, from.px[src].epoch);  // the epoch moves with the content
      float px, py, d;
      ASSERT_TRUE(project_point(b, p, px, py, d));
      if (to.marks[t] == kMarkMoved) {
        EXPECT_NEAR(px, float(x) + 0.5f, 0.5f + 1e-4f);  // inside its pixel
        EXPECT_NEAR(py, float(y) + 0.5f, 0.5f + 1e-4f);
        // project_point inverts camera_ray: the new camera's ray there passes through the point.
        const Ray ray = camera_ray(b, px, py);
        const Vec3 off = p.p - ray.org;
        EXPECT_LT(glm::length(glm::cross(ray.dir, off)), 1e-5f * glm::length(off));
        EXPECT_NEAR(d, glm::dot(off, b.w), 1e-5f * d);
        EXPECT_NEAR(d, to.points[t].depth, 1e-5f * d);  // the depth kept is the depth along the view axis
      } else {
        // A plane hides nothing: where the old camera saw the new pixel's point (3 pixels in from
        // its border), holes are cracks, filled from a close neighbour.
        ASSERT_TRUE(to.marks[t] & kMarkGuess);
        float ax, ay, ad;
        const ScenePoint h = hit(b, float(x) + 0.5f, float(y) + 0.5f, false);
        const bool seen = project_point(a, h, ax, ay, ad);
        if (seen && ax >= 3 && ay >= 3 && ax < kW - 3 && ay < kH - 3) {
          ++cracks;
          crack_marked_uncovered += to.marks[t] == kMarkDisoccluded;
          // A crack takes a neighbour; a wider hole the farthest content within 4 pixels.
          const float reach = to.marks[t] == kMarkFilled ? 1.5f : 5.5f;
          EXPECT_LE(std::fabs(sx_of(b, q) - (float(x) + 0.5f)), reach) << x << "," << y;
          EXPECT_LE(std::fabs(sy_of(b, q) - (float(y) + 0.5f)), reach) << x << "," << y;
        }
      }
    }
  EXPECT_GT(cracks, 0u);
  EXPECT_LE(crack_marked_uncovered * 10, cracks);  // mostly told apart from disocclusions
}

TEST(Reproject, UncoveredPixelsAreMarkedAndFilledFromBehind) {
  const CameraBasis a = basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f});
  const CameraBasis b = basis({0.5f, 0.0f, 5.0f}, {0.5f, 0.0f, 0.0f});  // sideways: parallax
  Synthetic from = render(a, true), to = render(a, true);
  Reprojector r;
  const ReprojectStats st = r.run(a, b, from.image(), to.image());
  EXPECT_GT(st.disoccluded, 0u);
  size_t uncovered = 0;
  for (int y = 1; y + 1 < kH; ++y)
    for (int x = 1; x + 1 < kW; ++x) {
      // What the new camera sees at the pixel centre, and whether the old one saw that point.
      bool sq = false;
      const ScenePoint q = hit(b, float(x) + 0.5f, float(y) + 0.5f, true, &sq);
      const size_t t = size_t(y) * kW + size_t(x);
      if (sq) continue;
      float ax, ay, ad;
      if (!project_point(a, q, ax, ay, ad)) continue;  // outside the old view: not behind the square
      bool hidden = false;
      hit(a, ax, ay, true, &hidden);
      if (!hidden) continue;
      ++uncovered;
      EXPECT_TRUE(to.marks[t] & kMarkGuess) << x << "," << y;  // marked: render it first
      EXPECT_EQ(to.px[t].rgb[2], 1.0f) << x << "," << y;     // background, not the square's edge
    }
  EXPECT_GT(uncovered, 20u);
}

TEST(Reproject, PointsThatMayMoveAreMarkedStaleWhenTheWorldMoves) {
  const CameraBasis a = basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f});
  const CameraBasis b = basis({0.1f, 0.0f, 5.0f}, {0.1f, 0.0f, 0.0f});
  Synthetic from = render(a, false), to = render(a, false);
  for (size_t i = 0; i < from.world.size(); i += 2) from.world[i].object = kPointDynamic + 3;
  from.encode();
  Reprojector r;
  const ReprojectStats st = r.run(a, b, from.image(), to.image());
  EXPECT_GT(st.stale, size_t(kW * kH) / 3);
  for (size_t t = 0; t < to.points.size(); ++t)
    EXPECT_EQ(bool(to.marks[t] & kMarkStale), view_kind(to.points[t].bits) == kViewMoving) << t;
  // While nothing in the world has moved, instances and dynamic objects are where they were.
  const ReprojectStats still_world = r.run(a, b, from.image(), to.image(), false);
  EXPECT_EQ(still_world.stale, 0u);
}

// Each step moves what the last one left: copies of a neighbour carry points of their own, so an
// orbit does not lose more of the image with every step (with copied points, which collide with
// their originals, 75 % of the pixels still landed after eight steps; now 85 %).
TEST(Reproject, RepeatedStepsKeepTheImageWhole) {
  Synthetic cur = render(basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}), false), next = cur;
  Reprojector r;
  ReprojectStats st;
  CameraBasis before = cur.camera;
  for (int k = 1; k <= 8; ++k) {
    const float angle = 0.015f * float(k);  // an orbit, about 1.5 pixels a step
    const CameraBasis after = basis({5.0f * std::sin(angle), 0.0f, 5.0f * std::cos(angle)}, {0.0f, 0.0f, 0.0f});
    st = r.run(before, after, cur.image(), next.image());
    before = after;
    std::swap(cur, next);
  }
  const size_t n = size_t(kW) * kH;
  EXPECT_GT(st.moved, n * 80 / 100) << "filled " << st.filled << ", disoccluded " << st.disoccluded;
}

// Many holes (a wide step) take the by-rows search; it must pick exactly what the per-hole window
// picks (the farthest landed pixel within reach, ties to the lower index), so the images match.
// Two reprojections of one image gave the same result, bit for bit.
void expect_same_image(const Synthetic& a, const ReprojectStats& sa, const Synthetic& b, const ReprojectStats& sb) {
  EXPECT_EQ(sa.moved, sb.moved);
  EXPECT_EQ(sa.filled, sb.filled);
  EXPECT_EQ(sa.disoccluded, sb.disoccluded);
  EXPECT_EQ(sa.stale, sb.stale);
  EXPECT_EQ(std::memcmp(a.px.data(), b.px.data(), a.px.size() * sizeof(DisplayPixel)), 0);
  EXPECT_EQ(std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(ViewPoint)), 0);
  EXPECT_EQ(a.marks, b.marks);
}

// Radius 3 (the default) takes the vector window where the build has AVX-512, radius 5 the
// scalar one; both must pick what the row search picks.
TEST(Reproject, RowSearchMatchesTheWindowSearch) {
  const CameraBasis a = basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f});
  const CameraBasis b = basis({1.2f, 0.3f, 3.5f}, {0.8f, 0.2f, 0.0f});
  Synthetic from = render(a, true);
  for (size_t i = 0; i < from.world.size(); i += 7) from.world[i].object = kPointNone;  // holes
  from.encode();
  for (const int radius : {3, 5}) {
    SCOPED_TRACE(radius);
    Synthetic window = from, rows = from;
    Reprojector r;
    r.set_search(Reprojector::Search::window);
    const ReprojectStats sw = r.run(a, b, from.image(), window.image(), true, radius);
    r.set_search(Reprojector::Search::rows);
    const ReprojectStats sr = r.run(a, b, from.image(), rows.image(), true, radius);
    EXPECT_GT(sw.disoccluded, size_t(kW * kH) / 8);
    expect_same_image(window, sw, rows, sr);
  }
}

// The vector paths (splat, hole scan, disocclusion window) give the scalar code's image, bit for
// bit, on a scene with sky, moving objects, cracks, edges, disocclusions and a band of new view.
TEST(Reproject, VectorPathsMatchTheScalarCode) {
  const CameraBasis a = basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f});
  const CameraBasis b = basis({1.2f, 0.3f, 3.5f}, {0.8f, 0.2f, 0.0f});
  Synthetic from = render(a, true);
  for (size_t i = 0; i < from.world.size(); i += 11) from.world[i].object = kPointNone;  // holes
  for (size_t i = 5; i < from.world.size(); i += 13) from.world[i].object = kPointDynamic + uint32_t(i % 3);
  for (size_t i = 0; i < from.world.size(); ++i)  // depth steps of 3 % (cracks) and 6 % (edges)
    from.world[i].p = a.eye + (from.world[i].p - a.eye) * (1.0f + 0.03f * float(i * 7 % 3));
  for (int y = 0; y < kH / 5; ++y)  // sky along the top: its points are directions
    for (int x = 0; x < kW; ++x)
      from.world[size_t(y) * kW + size_t(x)] = {camera_ray(a, float(x) + 0.5f, float(y) + 0.5f).dir, kPointSky};
  from.encode();
  Synthetic vec = from, scalar = from;
  Reprojector r;
  r.set_search(Reprojector::Search::window);
  const ReprojectStats sv = r.run(a, b, from.image(), vec.image());
  r.set_vectorized(false);
  const ReprojectStats ss = r.run(a, b, from.image(), scalar.image());
  EXPECT_GT(ss.filled, 0u);
  EXPECT_GT(ss.disoccluded, 0u);
  EXPECT_GT(ss.stale, 0u);
  expect_same_image(vec, sv, scalar, ss);
  // In the display's slot order the gather takes two passes, the first one vectorized too.
  PartitionConfig pc;
  pc.width = kW, pc.height = kH, pc.threads = 3;
  const std::vector<uint32_t> pixel_of = slot_order(make_partition(pc));
  std::vector<uint32_t> slot_of(pixel_of.size());
  for (size_t s = 0; s < pixel_of.size(); ++s) slot_of[pixel_of[s]] = uint32_t(s);
  const auto slotted = [&](Synthetic& img) {
    return SlotImage{kW, kH, pixel_of.data(), slot_of.data(), img.px.data(), img.points.data(), img.marks.data()};
  };
  Synthetic in_slots = from, vec_slots = from, scalar_slots = from;
  for (size_t s = 0; s < pixel_of.size(); ++s) in_slots.px[s] = from.px[pixel_of[s]];
  r.set_vectorized(true);
  const ReprojectStats svs = r.run(a, b, slotted(in_slots), slotted(vec_slots));
  r.set_vectorized(false);
  const ReprojectStats sss = r.run(a, b, slotted(in_slots), slotted(scalar_slots));
  EXPECT_GT(sss.stale, 0u);
  expect_same_image(vec_slots, svs, scalar_slots, sss);
}

// The vector paths step eight pixels of a row and leave the border to the scalar code; images
// narrower or shorter than that (down to one pixel) must still give the scalar image.
TEST(Reproject, SmallImagesMatchTheScalarCode) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {2, 7}, {3, 3}, {10, 4}, {17, 5}, {33, 9}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    const CameraBasis a = look_at_basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, w, h);
    const CameraBasis b = look_at_basis({0.4f, 0.1f, 4.2f}, {0.0f, 0.0f, 0.0f}, w, h);
    const size_t n = size_t(w) * size_t(h);
    std::vector<DisplayPixel> px(n);
    std::vector<ScenePoint> world(n);
    std::vector<uint8_t> marks(n, kMarkNone);
    for (size_t i = 0; i < n; ++i) {
      const Ray r = camera_ray(a, float(i % size_t(w)) + 0.5f, float(i / size_t(w)) + 0.5f);
      world[i] = {r.org + (-r.org.z / r.dir.z) * (1.0f + 0.03f * float(i * 7 % 3)) * r.dir, kPointStatic};
      if (i % 5 == 3) world[i].object = kPointNone;
      px[i].rgb[0] = float(i);
    }
    std::vector<ViewPoint> points = Synthetic::encode_points(a, world);
    std::vector<DisplayPixel> vpx(n), spx(n);
    std::vector<ViewPoint> vpoints(n), spoints(n);
    std::vector<uint8_t> vmarks(n), smarks(n);
    const SlotImage from{w, h, nullptr, nullptr, px.data(), points.data(), marks.data()};
    Reprojector r;
    const ReprojectStats sv = r.run(a, b, from, {w, h, nullptr, nullptr, vpx.data(), vpoints.data(), vmarks.data()});
    r.set_vectorized(false);
    const ReprojectStats ss = r.run(a, b, from, {w, h, nullptr, nullptr, spx.data(), spoints.data(), smarks.data()});
    EXPECT_EQ(sv.moved, ss.moved);
    EXPECT_EQ(sv.filled, ss.filled);
    EXPECT_EQ(sv.disoccluded, ss.disoccluded);
    EXPECT_EQ(std::memcmp(vpx.data(), spx.data(), n * sizeof(DisplayPixel)), 0);
    EXPECT_EQ(std::memcmp(vpoints.data(), spoints.data(), n * sizeof(ViewPoint)), 0);
    EXPECT_EQ(vmarks, smarks);
    EXPECT_GE(sv.moved + sv.disoccluded + sv.filled, n);  // every pixel shows something
  }
}

// The census the gather counts is exact: each epoch the moved image shows, as often as it shows
// it, with epoch 0 (never rendered: not counted) among them and epochs that share the census's
// buckets (512 with 0; epochs spread over 200 and over 900 changes).
TEST(Reproject, TheCensusCountsEveryEpochShown) {
  const CameraBasis a = basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f});
  const CameraBasis b = basis({1.2f, 0.3f, 3.5f}, {0.8f, 0.2f, 0.0f});
  for (const uint32_t span : {200u, 900u}) {
    SCOPED_TRACE("epochs over " + std::to_string(span) + " changes");
    Synthetic from = render(a, true);
    for (size_t i = 0; i < from.world.size(); i += 11) from.world[i].object = kPointNone;
    from.encode();
    for (size_t i = 0; i < from.px.size(); ++i)  // 0, 512, and others spread over `span` changes
      from.px[i].epoch = i % 7 == 0 ? 0u : i % 7 == 1 ? 512u : 500u + uint32_t(i * 37 % 97) * (span / 100u);
    Synthetic to = from;
    Reprojector r;
    EpochCensus census;
    census.clear();
    r.run(a, b, from.image(), to.image(), true, 3, &census);
    EpochCensus expected;
    expected.clear();
    for (const DisplayPixel& p : to.px) expected.add(p.epoch);
    size_t shown = 0;
    for (const DisplayPixel& p : to.px) {
      EXPECT_EQ(census.of(p.epoch), expected.of(p.epoch)) << "epoch " << p.epoch;
      shown += p.epoch == 512u;
    }
    EXPECT_GT(shown, 0u);
    EXPECT_EQ(census.of(512u), shown);
    EXPECT_EQ(census.of(0u), 0u);
  }
}

// The display keeps its pixels in the engine's slot order (shuffled 64-pixel chunks of a Hilbert
// line, dealt to threads); the gather then walks pixels and slots in two passes. The image must
// be the one reprojected in pixel order, each pixel in its slot.
TEST(Reproject, SlotOrderGivesThePixelOrderImage) {
  const CameraBasis a = basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f});
  const CameraBasis b = basis({1.2f, 0.3f, 3.5f}, {0.8f, 0.2f, 0.0f});
  Synthetic from = render(a, true);
  for (size_t i = 0; i < from.world.size(); i += 11) from.world[i].object = kPointNone;
  from.encode();
  PartitionConfig pc;
  pc.width = kW, pc.height = kH, pc.threads = 3;
  const std::vector<uint32_t> pixel_of = slot_order(make_partition(pc));
  std::vector<uint32_t> slot_of(pixel_of.size());
  for (size_t s = 0; s < pixel_of.size(); ++s) slot_of[pixel_of[s]] = uint32_t(s);
  ASSERT_NE(pixel_of[1], 1u) << "the layout should not be the identity";
  Synthetic by_pixel = from;
  Reprojector r;
  const ReprojectStats sp = r.run(a, b, from.image(), by_pixel.image());
  Synthetic slotted = from, slotted_out = from;
  for (size_t s = 0; s < pixel_of.size(); ++s) slotted.px[s] = from.px[pixel_of[s]];
  const auto slot_image = [&](Synthetic& img) {
    return SlotImage{kW, kH, pixel_of.data(), slot_of.data(), img.px.data(), img.points.data(), img.marks.data()};
  };
  const ReprojectStats ss = r.run(a, b, slot_image(slotted), slot_image(slotted_out));
  EXPECT_GT(ss.filled, 0u);
  EXPECT_GT(ss.disoccluded, 0u);
  Synthetic back = slotted_out;  // by pixel again
  for (size_t s = 0; s < pixel_of.size(); ++s) back.px[pixel_of[s]] = slotted_out.px[s];
  expect_same_image(by_pixel, sp, back, ss);
}

// The CPU budget is a leaky bucket: a reprojection that cost c at budget b waits c / b seconds.
TEST(Reproject, BudgetSpacesReprojectionsByTheirCost) {
  ReprojectBudget budget;
  EXPECT_TRUE(budget.allow(10.0, 0.25f));
  budget.spend(0.05, 0.25f);                // 50 ms of CPU: the next one waits 200 ms
  EXPECT_FALSE(budget.allow(10.1, 0.25f));
  EXPECT_FALSE(budget.allow(10.19, 0.25f));
  EXPECT_TRUE(budget.allow(10.201, 0.25f));
  budget.spend(0.05, 0.25f);
  // A long pause banks at most one reprojection's cost: two in a row are not allowed after it.
  EXPECT_TRUE(budget.allow(100.0, 0.25f));
  budget.spend(0.05, 0.25f);
  EXPECT_TRUE(budget.allow(100.0, 0.25f));
  budget.spend(0.05, 0.25f);
  EXPECT_FALSE(budget.allow(100.0, 0.25f));
  EXPECT_TRUE(budget.allow(100.0, 0.0f));  // no budget: always
}

// Reprojections without a budget leave no debt: a budget turned on later (set_config) allows the
// next one at once and then spaces them, instead of waiting out the CPU of every earlier one.
TEST(Reproject, UnlimitedReprojectionsBankNoDebt) {
  ReprojectBudget budget;
  for (int k = 0; k < 1000; ++k) budget.spend(0.02, 0.0f);  // 20 s of CPU, unlimited
  EXPECT_TRUE(budget.allow(50.0, 0.25f));
  budget.spend(0.02, 0.25f);
  EXPECT_FALSE(budget.allow(50.01, 0.25f));
  EXPECT_TRUE(budget.allow(50.081, 0.25f));
}

// A point is read whole: under its own sequence lock none while its owner writes it, and inside
// the state's lock only the point of the update asked for. Against writers that keep alternating
// two points (store_point itself, and one that pauses between the components, as a preempted
// render thread does), every read is one of them whole; plain loads of the components mix them.
TEST(Reproject, PointsAreReadWholeInsideTheirSequenceLock) {
  PixelState state;
  PixelPoint slot;
  SampleResult near_hit, sky;
  near_hit.position = Vec3(1.0f, 2.0f, 3.0f);
  near_hit.object = kPointStatic;
  sky.position = Vec3(-40.0f, 50.0f, -60.0f);
  sky.object = kPointSky;
  const double mean[3] = {0.0, 0.0, 0.0};
  const auto publish = [&](const SampleResult& r) {
    return publish_state(state, 1, 1, mean, 0.0, Vec3(0.5f), 0.0f, [&] { store_point(slot, r); });
  };
  const uint32_t seq = publish(near_hit);
  ScenePoint p;
  ASSERT_TRUE(read_point_of(state, seq, slot, p));
  EXPECT_EQ(p.object, kPointStatic);
  EXPECT_EQ(p.p, near_hit.position);
  const uint32_t seq2 = publish(sky);
  EXPECT_FALSE(read_point_of(state, seq, slot, p));  // that update was replaced
  ASSERT_TRUE(read_point_of(state, seq2, slot, p));
  EXPECT_EQ(p.object, kPointSky);
  const uint32_t s = slot.seq.load();
  slot.seq.store(s + 1);  // the owner is writing the point
  EXPECT_FALSE(read_point(slot, p));
  slot.seq.store(s);

  for (const bool pause : {false, true}) {
    std::atomic<bool> stop{false};
    std::thread writer([&] {
      for (uint32_t k = 0; !stop.load(std::memory_order_relaxed); ++k) {
        const SampleResult& r = k % 2 ? sky : near_hit;
        if (!pause) {
          publish(r);
          continue;
        }
        const uint32_t v = slot.seq.load(std::memory_order_relaxed);  // store_point, paused
        slot.seq.store(v + 1, std::memory_order_relaxed);
        std::atomic_thread_fence(std::memory_order_release);
        for (int c = 0; c < 3; ++c) {
          slot.p[c].store(r.position[c], std::memory_order_relaxed);
          for (int spin = 0; spin < 64; ++spin) (void)stop.load(std::memory_order_relaxed);
        }
        slot.object.store(r.object, std::memory_order_relaxed);
        slot.seq.store(v + 2, std::memory_order_release);
      }
    });
    size_t reads = 0, torn = 0;
    // At least 200,000 attempts, and on until 100 reads succeeded: a loaded machine may run the
    // writer for whole time slices in which every attempt meets an odd sequence.
    for (int k = 0; k < 200000 || (reads < 100 && k < 50000000); ++k) {
      if (!read_point(slot, p)) continue;
      ++reads;
      const bool whole = (p.object == kPointStatic && p.p == near_hit.position) ||
                         (p.object == kPointSky && p.p == sky.position);
      torn += !whole;
    }
    stop = true;
    writer.join();
    EXPECT_GT(reads, 0u) << "pause " << pause;
    EXPECT_EQ(torn, 0u) << "of " << reads << " reads, pause " << pause;
  }
}

}  // namespace
}  // namespace frameless
