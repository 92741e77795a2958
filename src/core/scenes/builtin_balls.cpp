// The built-in "balls" scene: Parker's bouncing balls (seed figure 2) as real physics.
#include "core/base/rng.h"
#include "core/scene/scene_build.h"
#include "core/scenes/builtin_scenes.h"

namespace frameless {

std::unique_ptr<Scene> make_balls() {
  constexpr int kGrid = 4;          // 4 x 4 balls
  constexpr float kRadius = 0.45f;
  constexpr float kHalfBox = 4.0f;  // invisible walls at x, z = +-kHalfBox keep them in view
  auto s = std::make_unique<Scene>();
  s->name = "balls";
  Material floor_mat;
  floor_mat.name = "floor";
  floor_mat.kd = Vec3(0.65f);
  const uint16_t floor = add_material(*s, floor_mat);
  add_quad(*s, Vec3(0.0f), Vec3(0, 1, 0), 24.0f, floor);
  const Vec3 colours[6] = {{0.85f, 0.20f, 0.15f}, {0.95f, 0.70f, 0.15f}, {0.20f, 0.65f, 0.25f},
                           {0.15f, 0.35f, 0.85f}, {0.60f, 0.25f, 0.75f}, {0.90f, 0.90f, 0.88f}};
  uint16_t mats[6];
  for (int k = 0; k < 6; ++k) {
    Material m;
    m.name = "ball" + std::to_string(k);
    if (k % 3 == 2) {  // every third colour a metal, the rest polished plastic
      m.cls = MaterialClass::kMetal;
      m.kd = Vec3(0.0f);
      m.ks = m.kh = colours[k];
      m.phong_exponent = 150.0f;
    } else {
      m.cls = MaterialClass::kPolished;
      m.kd = colours[k];
      m.r0 = Vec3(0.05f);
      m.kh = Vec3(0.8f);
      m.phong_exponent = 120.0f;
    }
    mats[k] = add_material(*s, m);
  }
  // Start on a grid at varied heights with a sideways push; the simulation does the rest.
  std::vector<BallState> balls;
  Rng rng(0xba11u);
  const float spacing = 1.6f, off = 0.5f * float(kGrid - 1) * spacing;
  for (int i = 0; i < kGrid * kGrid; ++i) {
    BallState b;
    b.radius = kRadius;
    b.center = Vec3(float(i % kGrid) * spacing - off, kRadius + 0.5f + 2.5f * rng.next_float(),
                    float(i / kGrid) * spacing - off);
    b.velocity = Vec3(2.0f * rng.next_float() - 1.0f, 0.0f, 2.0f * rng.next_float() - 1.0f);
    balls.push_back(b);
  }
  BallWorld world;
  world.box_lo = Vec3(-kHalfBox, 0.0f, -kHalfBox);
  world.box_hi = Vec3(kHalfBox, 100.0f, kHalfBox);
  const std::vector<Trajectory> paths = simulate_balls(world, balls);
  for (size_t i = 0; i < balls.size(); ++i) {
    DynamicObject o;
    o.name = "ball" + std::to_string(i);
    o.sphere = Sphere{balls[i].center, balls[i].radius};
    o.material = mats[(i * 7) % 6];
    o.motion.kind = MotionKind::kTrajectory;
    o.motion.trajectory = paths[i];
    s->dynamic.push_back(std::move(o));
  }
  // A spherical light: the soft shadows of figure 2.
  Light light;
  light.position = Vec3(-4.0f, 9.0f, 6.0f);
  light.color = Vec3(0.9f);
  light.radius = 0.6f;
  s->lights.push_back(light);
  s->ambient = default_hemisphere_ambient();
  s->camera.eye = Vec3(0.0f, 6.0f, 10.0f);
  s->camera.look = Vec3(0.0f, 0.8f, 0.0f);
  s->camera.fov_deg = 45.0f;
  return s;
}

}  // namespace frameless
