// Camera path interpolation: keyframes are hit exactly, motion is smooth, cuts jump, files parse.
#include "display/camera_path.h"

#include <gtest/gtest.h>

namespace frameless {
namespace {

Camera cam(Vec3 eye, Vec3 look, float fov = 45.0f) {
  Camera c;
  c.eye = eye;
  c.look = look;
  c.fov_deg = fov;
  return c;
}

// Same image basis (what the renderer sees), ignoring how `up` was written.
void expect_same_view(const Camera& a, const Camera& b, float tol) {
  const CameraBasis x = make_camera_basis(a, 4, 3), y = make_camera_basis(b, 4, 3);
  EXPECT_NEAR(glm::length(x.eye - y.eye), 0.0f, tol);
  EXPECT_NEAR(glm::length(x.u - y.u), 0.0f, tol);
  EXPECT_NEAR(glm::length(x.v - y.v), 0.0f, tol);
  EXPECT_NEAR(glm::length(x.w - y.w), 0.0f, tol);
  EXPECT_NEAR(a.fov_deg, b.fov_deg, tol);
}

CameraPath four_keys() {
  CameraPath p;
  p.keyframes = {{0.0, cam({0, 0, 5}, {0, 0, 0})},
                 {1.0, cam({5, 0, 0}, {0, 0, 0}, 50.0f)},
                 {2.5, cam({0, 2, -5}, {0, 1, 0})},
                 {3.0, cam({-5, 0, 0}, {0, 0, 0}, 30.0f)}};
  return p;
}

TEST(CameraPath, PassesThroughEveryKeyframe) {
  const CameraPath p = four_keys();
  for (const CameraKeyframe& k : p.keyframes)
    expect_same_view(evaluate_camera_path(p, k.time), k.camera, 1e-5f);
  // Held before the start and after the end.
  expect_same_view(evaluate_camera_path(p, -1.0), p.keyframes.front().camera, 1e-6f);
  expect_same_view(evaluate_camera_path(p, 9.0), p.keyframes.back().camera, 1e-6f);
}

TEST(CameraPath, MotionIsContinuousWithContinuousVelocity) {
  const CameraPath p = four_keys();
  const double dt = 1e-4;
  for (double t : {1.0, 2.5}) {  // interior keyframes: where a piecewise-linear path would kink
    const Vec3 before = evaluate_camera_path(p, t - dt).eye, at = evaluate_camera_path(p, t).eye,
               after = evaluate_camera_path(p, t + dt).eye;
    const Vec3 v_in = (at - before) / float(dt), v_out = (after - at) / float(dt);
    EXPECT_LT(glm::length(v_in - v_out), 0.02f * glm::length(v_in)) << "t=" << t;
  }
  // Small steps give small changes everywhere (no jumps without a cut).
  Camera prev = evaluate_camera_path(p, 0.0);
  for (double t = 0.001; t <= 3.0; t += 0.001) {
    const Camera c = evaluate_camera_path(p, t);
    ASSERT_TRUE(camera_is_valid(c));
    EXPECT_LT(glm::length(c.eye - prev.eye), 0.05f) << t;
    EXPECT_LT(glm::length(c.look - prev.look), 0.05f) << t;
    prev = c;
  }
}

TEST(CameraPath, OrientationSlerpsAtConstantRate) {
  CameraPath p;
  p.keyframes = {{0.0, cam({0, 0, 0}, {0, 0, -1})}, {1.0, cam({0, 0, 0}, {1, 0, 0})}};
  // A 90 degree turn in place: at t=1/3 the view has turned 30 degrees.
  const Camera c = evaluate_camera_path(p, 1.0 / 3.0);
  const Vec3 d = glm::normalize(c.look - c.eye);
  EXPECT_NEAR(std::atan2(d.x, -d.z) * 180.0f / kPi, 30.0f, 1e-3f);
}

TEST(CameraPath, OrbitShorthandStaysOnTheCircle) {
  const Camera start = cam({0, 1, 4}, {0, 1, 0});
  PathShorthand sh;
  sh.orbit_deg = 360.0;
  const CameraPath p = make_shorthand_path(start, sh, 6.0);
  for (double t = 0.0; t <= 6.0; t += 0.05) {
    const Camera c = evaluate_camera_path(p, t);
    EXPECT_NEAR(glm::length(c.eye - start.look), 4.0f, 4.0f * 2e-4f) << t;
    EXPECT_NEAR(glm::length(glm::normalize(c.look - c.eye) - glm::normalize(start.look - c.eye)), 0.0f,
                1e-3f);
  }
  expect_same_view(evaluate_camera_path(p, 6.0), start, 1e-4f);
  const Camera quarter = evaluate_camera_path(p, 1.5);
  EXPECT_NEAR(std::abs(quarter.eye.x), 4.0f, 1e-3f);
}

TEST(CameraPath, DollyAndCut) {
  const Camera start = cam({0, 0, 8}, {0, 0, 0});
  PathShorthand sh;
  sh.dolly_factor = 0.5;
  sh.cut_at = 1.0;
  sh.cut_orbit_deg = 90.0;
  const CameraPath p = make_shorthand_path(start, sh, 2.0);
  // Before the cut the eye approaches along +z; right after it the view has turned 90 degrees.
  const Camera before = evaluate_camera_path(p, 0.999);
  const Camera after = evaluate_camera_path(p, 1.0);
  EXPECT_NEAR(before.eye.x, 0.0f, 1e-3f);
  EXPECT_GT(before.eye.z, 5.6f);
  EXPECT_NEAR(std::abs(after.eye.x), 8.0f * std::sqrt(0.5f), 1e-2f);
  EXPECT_NEAR(after.eye.z, 0.0f, 1e-3f);
  EXPECT_NEAR(glm::length(evaluate_camera_path(p, 2.0).eye), 4.0f, 1e-3f);
}

TEST(CameraPath, JsonRoundTrip) {
  CameraPath p = four_keys();
  p.keyframes[2].cut = true;
  auto back = parse_camera_path(camera_path_to_json(p, "test"), "mem.json");
  ASSERT_TRUE(back.ok()) << back.error().message;
  ASSERT_EQ(back->keyframes.size(), p.keyframes.size());
  for (size_t i = 0; i < p.keyframes.size(); ++i) {
    EXPECT_EQ(back->keyframes[i].time, p.keyframes[i].time);
    EXPECT_EQ(back->keyframes[i].cut, p.keyframes[i].cut);
    expect_same_view(back->keyframes[i].camera, p.keyframes[i].camera, 1e-6f);
  }
}

TEST(CameraPath, BadFilesNameTheField) {
  struct Case {
    const char* text;
    const char* expect;
  } cases[] = {
      {"{", "mem.json: "},
      {"{}", "keyframes: missing"},
      {R"({"keyframes": []})", "keyframes: empty"},
      {R"({"keyframes": [{"t": 0, "eye": [0,0,1]}]})", "keyframes[0].look"},
      {R"({"keyframes": [{"t": 0, "eye": [0,0,1], "look": [0,0,0]}, {"t": -1, "eye": [0,0,1], "look": [0,0,0]}]})",
       "keyframes[1].t"},
      {R"({"keyframes": [{"t": 1, "eye": [0,0,1], "look": [0,0,0]}, {"t": 0.5, "eye": [0,0,1], "look": [0,0,0]}]})",
       "keyframes[1].t: times must not decrease"},
      {R"({"keyframes": [{"t": 0, "eye": [0,0,0], "look": [0,0,0]}]})", "keyframes[0]: invalid camera"},
      {R"({"keyframes": [{"t": 0, "eye": [0,0,1], "look": [0,0,0], "fov": 200}]})", "invalid camera"},
      {R"({"keyframes": [{"t": 0, "eye": [0,"a",1], "look": [0,0,0]}]})", "keyframes[0].eye"},
  };
  for (const Case& c : cases) {
    auto r = parse_camera_path(c.text, "mem.json");
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_NE(r.error().message.find(c.expect), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
  }
  EXPECT_FALSE(load_camera_path("/nonexistent/path.json").ok());
}

TEST(CameraPath, WorldToCameraMapsEyeToOriginAndLookToMinusZ) {
  const Camera c = cam({1, 2, 3}, {1, 2, -7});
  const std::vector<float> m = world_to_camera_matrix(c);
  auto apply = [&](Vec3 p) {  // row vector times matrix
    Vec3 r;
    for (int col = 0; col < 3; ++col)
      r[col] = p.x * m[0 * 4 + col] + p.y * m[1 * 4 + col] + p.z * m[2 * 4 + col] + m[3 * 4 + col];
    return r;
  };
  EXPECT_NEAR(glm::length(apply(c.eye)), 0.0f, 1e-5f);
  const Vec3 l = apply(c.look);
  EXPECT_NEAR(l.z, -10.0f, 1e-4f);
  EXPECT_NEAR(l.x, 0.0f, 1e-5f);
}

}  // namespace
}  // namespace frameless
