// Scale robustness: a lit sphere on a plane shows no shadow acne at scales 1e-4, 1 and 1e6
// (checked pixel by pixel against a double-precision analytic answer), and a scene moved 1e5
// away from the origin shows the same shadowed fraction as at the origin (within 0.1%).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/scene/scene_finalize.h"
#include "core/shading/render_sample.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

using testing::add_horizontal_quad;
using testing::add_sphere;
using testing::make_empty_scene;
using testing::make_material;

using DVec3 = glm::dvec3;

// Sphere of radius r resting on the floor y = 0 at the origin, light up and to the side, all
// lengths multiplied by `scale` and moved by `offset`. No ambient, so shadow is exactly black.
struct ContactScene {
  std::unique_ptr<Scene> scene = make_empty_scene();
  CameraBasis camera;
  double scale;
  DVec3 offset, center, light;
  double radius;

  ContactScene(double scale_, DVec3 offset_, int w, int h) : scale(scale_), offset(offset_) {
    const Vec3 o(offset);
    const float s = float(scale);
    radius = 10.0 * scale;
    center = offset + DVec3(0.0, 10.0, 0.0) * scale;
    light = offset + DVec3(-60.0, 45.0, -40.0) * scale;
    scene->materials.push_back(make_material(MaterialClass::kDiffuse));
    add_sphere(scene->geometry, Vec3(center), float(radius), 0);
    add_horizontal_quad(scene->geometry, o.y, 100.0f * s, 0, true, o.x, o.z);
    scene->lights.push_back(Light{Vec3(light), Vec3(1.0f), 0.0f});
    scene->settings.background = Vec3(0.5f);
    finalize_scene(*scene);
    Camera cam;
    cam.eye = o + s * Vec3(0.0f, 40.0f, 60.0f);
    cam.look = o;
    cam.fov_deg = 50.0f;
    camera = make_camera_basis(cam, w, h);
  }

  // Analytic classification of the pixel-centre ray in double precision:
  // +1 lit with margin, -1 shadowed with margin, 0 near a boundary or a miss.
  int classify(int x, int y) const {
    const Ray r = camera_ray(camera, x + 0.5f, y + 0.5f);
    const DVec3 o(r.org), d(r.dir);
    DVec3 p, n;
    // Sphere first (it is in front of the floor wherever both are hit).
    const DVec3 oc = o - center;
    const double b = glm::dot(oc, d), c = glm::dot(oc, oc) - radius * radius;
    const double disc = b * b - c;
    const double margin = 0.02;
    if (disc > 0.0 && -b - std::sqrt(disc) > 0.0) {
      p = o + (-b - std::sqrt(disc)) * d;
      n = (p - center) / radius;
      const double nl = glm::dot(n, glm::normalize(light - p));
      return nl > margin ? 1 : (nl < -margin ? -1 : 0);
    }
    if (d.y >= 0.0) return 0;
    p = o + ((offset.y - o.y) / d.y) * d;
    if (std::abs(p.x - offset.x) > 100.0 * scale || std::abs(p.z - offset.z) > 100.0 * scale)
      return 0;
    // Distance from the sphere centre to the segment p -> light.
    const DVec3 seg = light - p;
    const double t = std::clamp(glm::dot(center - p, seg) / glm::dot(seg, seg), 0.0, 1.0);
    const double dist = glm::length(p + t * seg - center);
    return dist > radius * (1.0 + margin) ? 1 : (dist < radius * (1.0 - margin) ? -1 : 0);
  }
};

TEST(Scale, NoShadowAcneOrLeaksAtAnyScale) {
  const int w = 80, h = 60;
  for (double scale : {1e-4, 1.0, 1e6}) {
    ContactScene cs(scale, DVec3(0.0), w, h);
    int lit = 0, shadowed = 0, false_shadow = 0, leak = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const SampleResult r = render_sample(*cs.scene, cs.camera, x, y, 0, false);
        ASSERT_TRUE(r.valid);
        const bool black = r.color == Vec3(0.0f);
        switch (cs.classify(x, y)) {
          case 1:
            ++lit, false_shadow += black;
            break;
          case -1:
            ++shadowed, leak += !black;
            break;
          default:
            break;
        }
      }
    EXPECT_EQ(false_shadow, 0) << "scale " << scale;
    EXPECT_EQ(leak, 0) << "scale " << scale;
    // Enough of both kinds that the counts above mean something.
    EXPECT_GT(lit, w * h / 4) << "scale " << scale;
    EXPECT_GT(shadowed, w * h / 20)
        << "scale " << scale << " lit " << lit << " shadowed " << shadowed;
  }
}

double shadowed_fraction(const ContactScene& cs, int w, int h) {
  int black = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      black += render_sample(*cs.scene, cs.camera, x, y, 0, false).color == Vec3(0.0f);
  return double(black) / double(w * h);
}

TEST(Scale, TranslationBy1e5KeepsTheShadowedFraction) {
  const int w = 200, h = 150;
  const double at_origin = shadowed_fraction(ContactScene(1.0, DVec3(0.0), w, h), w, h);
  const double far = shadowed_fraction(ContactScene(1.0, DVec3(1e5, 1e5, 1e5), w, h), w, h);
  EXPECT_GT(at_origin, 0.05);
  EXPECT_LT(at_origin, 0.6);
  EXPECT_NEAR(far, at_origin, 1e-3);
  std::printf("shadowed fraction at origin %.5f, translated by 1e5 %.5f\n", at_origin, far);
}

}  // namespace
}  // namespace frameless
