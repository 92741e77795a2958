// Orbit, pan, zoom and fly keep the camera valid and move it the way a user expects.
#include "display/camera_controls.h"

#include <gtest/gtest.h>

namespace frameless {
namespace {

Camera base() {
  Camera c;
  c.eye = Vec3(0, 1, 5);
  c.look = Vec3(0, 1, 0);
  c.up = Vec3(0, 1, 0);
  return c;
}

TEST(CameraControls, OrbitKeepsDistanceAndLookPoint) {
  const Camera c = base();
  const Camera o = orbit_camera(c, 120.0f, -40.0f);
  EXPECT_EQ(o.look, c.look);
  EXPECT_NEAR(glm::length(o.eye - o.look), 5.0f, 1e-4f);
  EXPECT_GT(glm::length(o.eye - c.eye), 1.0f);
  // 300 px at 0.3 deg/px is a half turn: the eye ends behind the look-at point.
  const Camera half = orbit_camera(c, 600.0f, 0.0f);
  EXPECT_NEAR(half.eye.z, -5.0f, 1e-3f);
}

TEST(CameraControls, OrbitPitchStopsBeforeThePole) {
  Camera c = base();
  for (int i = 0; i < 100; ++i) c = orbit_camera(c, 0.0f, 50.0f);
  ASSERT_TRUE(camera_is_valid(c));
  const Vec3 dir = glm::normalize(c.eye - c.look);
  EXPECT_LT(dir.y, std::sin(89.5f * kPi / 180.0f));
  EXPECT_GT(dir.y, std::sin(88.5f * kPi / 180.0f));
}

TEST(CameraControls, PanMovesEyeAndLookTogether) {
  const Camera c = base();
  const Camera p = pan_camera(c, 100.0f, 0.0f, 500);
  EXPECT_NEAR(glm::length((p.eye - c.eye) - (p.look - c.look)), 0.0f, 1e-5f);
  // Dragging right moves the camera left so the scene follows the cursor.
  EXPECT_LT(p.eye.x, c.eye.x);
  // One viewport height of drag moves the view by the visible height at the look distance.
  const Camera q = pan_camera(c, 0.0f, 500.0f, 500);
  EXPECT_NEAR(q.eye.y - c.eye.y, 2.0f * 5.0f * std::tan(22.5f * kPi / 180.0f), 1e-4f);
}

TEST(CameraControls, ZoomScalesDistanceAndClamps) {
  const Camera c = base();
  EXPECT_NEAR(glm::length(zoom_camera(c, 1.0f).eye - c.look), 5.0f * 0.85f, 1e-5f);
  EXPECT_NEAR(glm::length(zoom_camera(c, -1.0f).eye - c.look), 5.0f / 0.85f, 1e-4f);
  const Camera z = zoom_camera(c, 1e4f);
  EXPECT_TRUE(camera_is_valid(z));
  EXPECT_NEAR(glm::length(z.eye - z.look), 1e-3f, 1e-6f);
}

TEST(CameraControls, FlyForwardMovesAlongView) {
  const Camera c = base();
  const Camera f = fly_camera(c, 0.0f, 0.0f, 1.0f, 1.0f);
  EXPECT_NEAR(f.eye.z, 5.0f - 2.5f, 1e-5f);
  EXPECT_NEAR(f.look.z, -2.5f, 1e-5f);
  const Camera r = fly_camera(c, 1.0f, 0.0f, 0.0f, 1.0f);
  EXPECT_GT(r.eye.x, 0.0f);
  const Camera u = fly_camera(c, 0.0f, 1.0f, 0.0f, 1.0f);
  EXPECT_GT(u.eye.y, c.eye.y);
}

TEST(CameraControls, InvalidCameraIsReturnedUnchanged) {
  Camera bad = base();
  bad.look = bad.eye;
  EXPECT_EQ(orbit_camera(bad, 10.0f, 10.0f), bad);
  EXPECT_EQ(zoom_camera(bad, 1.0f), bad);
}

}  // namespace
}  // namespace frameless
