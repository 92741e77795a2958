// Objects that move while you look (core/scene/motion.h, core/scene/dynamic.h): motion as a function of
// time, the baked ball physics, the world state's flat form, and rendering at a given instant.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scene/dynamic.h"
#include "core/scene/scene.h"
#include "core/scene/scene_intersect.h"
#include "core/scenes/scene_load.h"
#include "core/shading/render_sample.h"
#include "core/shading/soft_shadow.h"

namespace frameless {
namespace {

TEST(Motion, BounceTouchesTheFloorAndPeaksAtHalfPeriod) {
  Motion m;
  m.kind = MotionKind::kBounce;
  m.bounce = Bounce{2.0f, 1.5f, 0.0f};
  EXPECT_NEAR(motion_offset(m, 0.0).y, 0.0f, 1e-6f);
  EXPECT_NEAR(motion_offset(m, 0.75).y, 2.0f, 1e-5f);
  EXPECT_NEAR(motion_offset(m, 1.5).y, 0.0f, 1e-5f);
  EXPECT_NEAR(motion_offset(m, 0.375).y, 1.5f, 1e-5f);  // h (1 - (2s - 1)^2) at s = 1/4
  EXPECT_EQ(motion_offset(m, std::nan("")), motion_offset(m, 0.0));  // never NaN
}

TEST(Motion, KeyframesInterpolateLoopAndHold) {
  Motion m;
  m.kind = MotionKind::kKeyframes;
  m.keys = {{0.0f, Vec3(0.0f)}, {1.0f, Vec3(2.0f, 0.0f, 0.0f)}, {3.0f, Vec3(2.0f, 4.0f, 0.0f)}};
  EXPECT_NEAR(motion_offset(m, 0.5).x, 1.0f, 1e-6f);
  EXPECT_NEAR(motion_offset(m, 2.0).y, 2.0f, 1e-6f);
  EXPECT_NEAR(motion_offset(m, 3.5).x, 1.0f, 1e-5f);  // looped: 3.5 is 0.5
  m.loop = false;
  EXPECT_EQ(motion_offset(m, 10.0), Vec3(2.0f, 4.0f, 0.0f));
  EXPECT_EQ(motion_offset(m, -1.0), Vec3(0.0f));
}

TEST(Motion, BallPhysicsStaysInTheBoxAndKeepsItsEnergy) {
  BallWorld w;
  w.duration = 20.0f;
  w.collisions = false;
  std::vector<BallState> balls = {{Vec3(0.0f, 3.0f, 0.0f), 0.5f, Vec3(1.5f, 0.0f, -0.7f)},
                                  {Vec3(2.0f, 1.0f, 1.0f), 0.3f, Vec3(-3.0f, 2.0f, 0.5f)}};
  const std::vector<Trajectory> paths = simulate_balls(w, balls);
  ASSERT_EQ(paths.size(), 2u);
  for (size_t b = 0; b < 2; ++b) {
    float top = 0.0f;
    for (size_t k = 0; k < paths[b].position.size(); ++k) {
      const Vec3 c = balls[b].center + paths[b].position[k];
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(c[a], w.box_lo[a] + balls[b].radius - 1e-3f);
        EXPECT_LE(c[a], w.box_hi[a] - balls[b].radius + 1e-3f);
      }
      top = std::max(top, c.y);
    }
    // Elastic bounces: the ball keeps reaching its starting energy's height (within 2 %).
    const float energy = 0.5f * balls[b].velocity.y * balls[b].velocity.y +
                         w.gravity * (balls[b].center.y - balls[b].radius);
    EXPECT_NEAR(top - balls[b].radius, energy / w.gravity, 0.02f * energy / w.gravity);
  }
  // The motion is a pure function of time: the same instant gives the same place.
  Motion m;
  m.kind = MotionKind::kTrajectory;
  m.trajectory = paths[0];
  EXPECT_EQ(motion_offset(m, 7.3), motion_offset(m, 7.3));
  // Ping-pong past the end: continuous at the turn.
  const double end = double(m.trajectory.step) * double(m.trajectory.position.size() - 1);
  EXPECT_LT(glm::length(motion_offset(m, end - 1e-3) - motion_offset(m, end + 1e-3)), 0.05f);
}

TEST(Motion, CollidingBallsSeparate) {
  BallWorld w;
  w.duration = 3.0f;
  w.gravity = 0.0f;
  std::vector<BallState> balls = {{Vec3(-2.0f, 1.0f, 0.0f), 0.5f, Vec3(2.0f, 0.0f, 0.0f)},
                                  {Vec3(2.0f, 1.0f, 0.0f), 0.5f, Vec3(-2.0f, 0.0f, 0.0f)}};
  const auto with = simulate_balls(w, balls);
  w.collisions = false;
  const auto without = simulate_balls(w, balls);
  float closest_with = 1e9f, closest_without = 1e9f;
  for (size_t k = 0; k < with[0].position.size(); ++k) {
    closest_with = std::min(closest_with, glm::length((balls[1].center + with[1].position[k]) -
                                                      (balls[0].center + with[0].position[k])));
    closest_without =
        std::min(closest_without, glm::length((balls[1].center + without[1].position[k]) -
                                              (balls[0].center + without[0].position[k])));
  }
  EXPECT_GT(closest_with, 0.95f);    // they bounce off each other (sum of radii 1)
  EXPECT_LT(closest_without, 0.1f);  // without collisions they pass through
}

constexpr const char* kMovingScene = R"({
  "camera": {"eye": [0, 10, 0.001], "look": [0, 0, 0], "fov": 60},
  "lights": [{"type": "spherical", "position": [0, 8, 0], "radius": 0.5, "color": [1, 1, 1]}],
  "materials": {"floor": {"class": "diffuse", "kd": [0.5, 0.5, 0.5]},
                "ball": {"class": "diffuse", "kd": [0.9, 0.1, 0.1]}},
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 20, "material": "floor"},
    {"type": "sphere", "center": [0, 1, 0], "radius": 0.5, "material": "ball",
     "motion": {"type": "keyframes", "loop": false,
                "keys": [{"time": 0, "translate": [-2, 0, 0]}, {"time": 1, "translate": [2, 0, 0]}]}}
  ]
})";

// Distance to the first hit through the world point (x, 0, 0) as seen from the camera.
float depth_toward(const Scene& s, const DynamicFrame* frame, float x) {
  Ray r;
  r.org = s.camera.eye;
  r.dir = glm::normalize(Vec3(x, 0.0f, 0.0f) - r.org);
  Hit h;
  return scene_intersect(s, frame, r, h) ? h.t : kInfinity;
}

TEST(Dynamic, ObjectsAppearWhereTheyShouldAtGivenTimes) {
  auto scene = parse_scene_json(kMovingScene, "moving.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Scene& s = **scene;
  ASSERT_EQ(s.dynamic.size(), 1u);
  EXPECT_EQ(s.geometry.num_spheres(), 0u);  // kept out of the static structure
  EXPECT_TRUE(s.features.has_dynamic);
  const WorldState w = initial_world(s);
  DynamicFrame f;
  const float floor = glm::length(s.camera.eye - Vec3(-2.0f, 0.0f, 0.0f));
  evaluate_frame(s, w, 0.0, f);
  EXPECT_LT(depth_toward(s, &f, -2.0f), floor - 1.0f);  // the ball is at x = -2 at t = 0
  EXPECT_NEAR(depth_toward(s, &f, 2.0f), floor, 1e-3f);
  evaluate_frame(s, w, 1.0, f);
  EXPECT_NEAR(depth_toward(s, &f, -2.0f), floor, 1e-3f);  // and at x = +2 at t = 1
  EXPECT_LT(depth_toward(s, &f, 2.0f), floor - 1.0f);
  advance_frame(s, w, 0.5, f);
  EXPECT_LT(depth_toward(s, &f, 0.0f), floor - 1.0f);  // half way at t = 0.5
  // The application side moves it too: its base position plus its own motion.
  WorldState moved = w;
  moved.object_position[0].z = 3.0f;
  evaluate_frame(s, moved, 0.5, f);
  EXPECT_NEAR(depth_toward(s, &f, 0.0f), glm::length(s.camera.eye), 1e-3f);
  // The full sample sees it: red where the ball is, grey floor elsewhere.
  evaluate_frame(s, w, 0.5, f);
  const CameraBasis b = make_camera_basis(s.camera, 64, 64);
  const SampleResult centre = render_sample(s, b, 32, 32, 0, false, &f);
  EXPECT_GT(centre.color.x, 2.0f * centre.color.y);
  evaluate_frame(s, w, 0.0, f);
  const SampleResult away = render_sample(s, b, 32, 32, 0, false, &f);
  EXPECT_LT(away.color.x, 1.2f * away.color.y);  // grey floor
}

TEST(Dynamic, MovingObjectsCastSoftShadows) {
  auto scene = parse_scene_json(kMovingScene, "moving.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  const Scene& s = **scene;
  DynamicFrame f;
  evaluate_frame(s, initial_world(s), 0.5, f);  // the ball is above the origin
  ShadowQuery q;
  q.org = Vec3(0.0f, 1e-4f, 0.0f);
  q.dir = Vec3(0.0f, 1.0f, 0.0f);
  q.tmax = 7.4f;
  q.half_angle = std::asin(0.5f / 8.0f);
  q.tan_half = std::tan(q.half_angle);
  EXPECT_EQ(soft_visibility(s, q, &f), 0.0f);  // umbra under the ball
  EXPECT_EQ(soft_visibility(s, q, nullptr), 1.0f);
  q.org = Vec3(0.55f, 1e-4f, 0.0f);  // under the ball's edge: penumbra
  q.dir = glm::normalize(Vec3(0.0f, 8.0f, 0.0f) - q.org);
  const float pen = soft_visibility(s, q, &f);
  EXPECT_GT(pen, 0.0f);
  EXPECT_LT(pen, 1.0f);
}

TEST(Dynamic, WorldStateRoundTripsAndRejectsBadValues) {
  auto scene = parse_scene_json(kMovingScene, "moving.json", ".");
  ASSERT_TRUE(scene) << scene.error().message;
  WorldState w = initial_world(**scene);
  w.object_position[0] = Vec3(1, 2, 3);
  w.lights[0].color = Vec3(0.25f);
  w.materials[1].kd = Vec3(0.1f, 0.2f, 0.3f);
  w.materials[1].emission = Vec3(2.0f, 1.0f, 0.5f);
  std::vector<float> flat;
  pack_world(w, flat);
  EXPECT_EQ(flat.size(), world_floats(**scene));
  WorldState back = initial_world(**scene);
  ASSERT_TRUE(unpack_world(flat.data(), flat.size(), back));
  EXPECT_EQ(back.object_position[0], Vec3(1, 2, 3));
  EXPECT_EQ(back.lights[0].color, Vec3(0.25f));
  EXPECT_EQ(back.materials[1].kd, Vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(back.materials[1].emission, Vec3(2.0f, 1.0f, 0.5f));
  WorldState keep = back;
  EXPECT_FALSE(unpack_world(flat.data(), flat.size() - 1, back));  // wrong size
  flat[0] = std::nanf("");
  EXPECT_FALSE(unpack_world(flat.data(), flat.size(), back));
  EXPECT_EQ(back.object_position[0], keep.object_position[0]);  // unchanged on failure
  pack_world(w, flat);
  flat[kObjectFloats + 6] = -1.0f;  // a negative light radius
  EXPECT_FALSE(unpack_world(flat.data(), flat.size(), back));
  pack_world(w, flat);
  flat[flat.size() - 1] = -0.5f;  // a negative emission
  EXPECT_FALSE(unpack_world(flat.data(), flat.size(), back));
}

TEST(Dynamic, BadMotionGetsAOneLineErrorNamingTheField) {
  std::string text = kMovingScene;
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    auto r = parse_scene_json(t, "m.json", ".");
    return r ? std::string() : r.error().message;
  };
  EXPECT_NE(with("\"time\": 1,", "\"time\": 0,").find("objects[1].motion.keys[1].time"),
            std::string::npos);
  EXPECT_NE(with("\"type\": \"keyframes\"", "\"type\": \"wobble\"").find("unknown motion"),
            std::string::npos);
  EXPECT_NE(with("\"loop\": false", "\"loop\": 3").find("objects[1].motion.loop"), std::string::npos);
  const std::string bounce = with(R"({"type": "keyframes", "loop": false,)",
                                  R"({"type": "bounce", "height": 1, "period": 1, "loop": false,)");
  EXPECT_NE(bounce.find("objects[1].motion"), std::string::npos) << bounce;  // bounce has no keys
}

}  // namespace
}  // namespace frameless
