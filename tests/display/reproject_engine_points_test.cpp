// Reprojection of pixels that show the engine's newest update (unmarked): their world points,
// read under each point's lock, are landed by the vector splats sixteen at a time; the image must
// be the scalar code's, bit for bit, on a scene with sky, static and moving surfaces, points
// that land nowhere (behind the eye, outside, none) and a batch left over at the end.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "display/reproject.h"
#include "frameless/pixel_points.h"
#include "reproject_cameras.h"

namespace frameless {
namespace {

constexpr int kImageW = 80, kImageH = 50;

struct EngineTestImage {
  std::vector<DisplayPixel> px;
  std::vector<ViewPoint> points;
  std::vector<uint8_t> marks;
  explicit EngineTestImage(size_t n) : px(n), points(n), marks(n) {}
  SlotImage slots(const PixelPoint* engine) {
    return {kImageW, kImageH, nullptr, nullptr, px.data(), points.data(), marks.data(), engine};
  }
};

TEST(ReprojectEnginePoints, VectorSplatLandsThemAsTheScalarCode) {
  const CameraBasis a = look_at_basis({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, kImageW, kImageH);
  const CameraBasis b = look_at_basis({0.9f, 0.4f, 4.0f}, {0.3f, 0.1f, 0.0f}, kImageW, kImageH);
  const size_t n = size_t(kImageW) * kImageH;
  EngineTestImage from(n);
  std::vector<PixelPoint> engine(n);
  size_t unmarked = 0;
  for (size_t i = 0; i < n; ++i) {
    const float x = float(i % kImageW) + 0.5f, y = float(i / kImageW) + 0.5f;
    const Ray r = camera_ray(a, x, y);
    const Vec3 on_plane = r.org + (-r.org.z / r.dir.z) * (1.0f + 0.03f * float(i * 7 % 3)) * r.dir;
    from.px[i].rgb[0] = float(i);
    from.px[i].epoch = 1 + uint32_t(i % 5);
    // Two pixels in five show the engine's point (unmarked); the rest moved content (marked).
    if (i % 5 < 2) {
      ++unmarked;
      from.marks[i] = kMarkNone;
      uint32_t object = kPointStatic + uint32_t(i % 3);
      Vec3 p = on_plane;
      if (i % 23 == 0) object = kPointDynamic + uint32_t(i % 4);
      if (i % 29 == 0) p = r.dir, object = kPointSky;
      if (i % 31 == 0) object = kPointNone;
      if (i % 37 == 0) p = a.eye + 3.0f * (a.eye - on_plane);  // behind both cameras
      SampleResult sample;  // written as a render thread writes it
      sample.position = p;
      sample.object = object;
      store_point(engine[i], sample);
      // What the marked arrays hold there is never read.
      from.points[i] = ViewPoint{1.0f, kViewCentre | kViewStatic << kViewKindShift};
    } else {
      from.marks[i] = kMarkMoved;
      size_t at = i;
      from.points[i] = to_view(a, {on_plane, kPointStatic}, at);
      if (at != i) from.points[i] = ViewPoint{};
    }
  }
  EngineTestImage vec(n), scalar(n);
  Reprojector r;
  const ReprojectStats sv = r.run(a, b, from.slots(engine.data()), vec.slots(nullptr));
  r.set_vectorized(false);
  const ReprojectStats ss = r.run(a, b, from.slots(engine.data()), scalar.slots(nullptr));
  EXPECT_GT(unmarked, n / 3);
  EXPECT_GT(ss.moved, n / 2);
  EXPECT_GT(ss.stale, 0u);  // the dynamic objects' points landed
  EXPECT_EQ(sv.moved, ss.moved);
  EXPECT_EQ(sv.filled, ss.filled);
  EXPECT_EQ(sv.disoccluded, ss.disoccluded);
  EXPECT_EQ(sv.stale, ss.stale);
  EXPECT_EQ(std::memcmp(vec.px.data(), scalar.px.data(), n * sizeof(DisplayPixel)), 0);
  EXPECT_EQ(std::memcmp(vec.points.data(), scalar.points.data(), n * sizeof(ViewPoint)), 0);
  EXPECT_EQ(vec.marks, scalar.marks);
  // Content of the engine's pixels moved: some pixel shows an unmarked source's colour.
  size_t from_engine = 0;
  for (size_t i = 0; i < n; ++i)
    if (vec.marks[i] & kMarkMoved) from_engine += size_t(vec.px[i].rgb[0]) % 5 < 2;
  EXPECT_GT(from_engine, n / 5);
}

}  // namespace
}  // namespace frameless
