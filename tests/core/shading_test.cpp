// Analytic tests of Parker's shading model: Schlick, energy, ambient, each material class by hand,
// exponential attenuation, total internal reflection, pruning and the depth limit.
#include "core/shading/shading.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/scene/scene_finalize.h"
#include "shading_scenes.h"

namespace frameless {
namespace {

using testing::add_horizontal_quad;
using testing::add_sphere;
using testing::make_empty_scene;
using testing::make_material;

void expect_near(const Vec3& got, const Vec3& want, float tol) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

TEST(Schlick, GivesR0AtNormalIncidenceAndOneAtGrazing) {
  for (float r0 : {0.0f, 0.04f, 0.5f, 0.9f}) {
    EXPECT_FLOAT_EQ(schlick(1.0f, r0), r0);
    EXPECT_FLOAT_EQ(schlick(0.0f, r0), 1.0f);
    // Monotone toward grazing, and within 1e-3 of 1 close to it.
    float prev = r0;
    for (float c = 1.0f; c >= 0.0f; c -= 0.01f) {
      const float k = schlick(c, r0);
      EXPECT_GE(k, prev - 1e-6f);
      prev = k;
    }
    EXPECT_NEAR(schlick(1e-4f, r0), 1.0f, 1e-3f);
    // The fifth power in between: (1 - 0.5)^5 = 1/32.
    EXPECT_FLOAT_EQ(schlick(0.5f, r0), r0 + (1.0f - r0) / 32.0f);
  }
  EXPECT_NEAR(r0_from_ior(1.5f), 0.04f, 1e-7f);
  EXPECT_EQ(r0_from_ior(1.0f), 0.0f);
  const Vec3 rgb = schlick(1.0f, Vec3(0.1f, 0.2f, 0.3f));
  expect_near(rgb, Vec3(0.1f, 0.2f, 0.3f), 1e-7f);
}

TEST(Schlick, ReflectionPlusTransmissionIsOne) {
  for (float eta : {1.0f / 1.5f, 1.0f / 1.33f, 1.0f, 1.33f, 1.5f, 2.4f}) {
    for (float c = 0.0f; c <= 1.0f; c += 0.05f) {
      const FresnelTerms f = dielectric_fresnel(c, eta, r0_from_ior(eta));
      EXPECT_FLOAT_EQ(f.ks + f.kt, 1.0f) << "eta " << eta << " cos " << c;
      EXPECT_GE(f.ks, 0.0f);
      EXPECT_GE(f.kt, 0.0f);
    }
  }
}

TEST(Fresnel, TotalInternalReflectionBeyondTheCriticalAngle) {
  const float eta = 1.5f;  // leaving glass into air
  const float critical = std::asin(1.0f / eta);
  const FresnelTerms beyond = dielectric_fresnel(std::cos(critical + 0.01f), eta, 0.04f);
  EXPECT_TRUE(beyond.total_internal_reflection);
  EXPECT_EQ(beyond.ks, 1.0f);
  EXPECT_EQ(beyond.kt, 0.0f);
  const FresnelTerms before = dielectric_fresnel(std::cos(critical - 0.01f), eta, 0.04f);
  EXPECT_FALSE(before.total_internal_reflection);
  EXPECT_LT(before.ks, 1.0f);
  // Entering never reflects totally.
  EXPECT_FALSE(dielectric_fresnel(0.0f, 1.0f / eta, 0.04f).total_internal_reflection);
  // Normal incidence from either side reflects exactly R0.
  EXPECT_FLOAT_EQ(dielectric_fresnel(1.0f, eta, 0.04f).ks, 0.04f);
  EXPECT_FLOAT_EQ(dielectric_fresnel(1.0f, 1.0f / eta, 0.04f).ks, 0.04f);
}

TEST(HemisphereAmbient, NusseltValuesAtKeyAngles) {
  const Vec3 a(1.0f, 0.5f, 0.25f), b(0.0f, 0.2f, 0.8f);
  const Vec3 axis = glm::normalize(Vec3(1.0f, 2.0f, -0.5f));
  // A normal at angle theta from the axis, rotating in a plane containing the axis.
  const Vec3 side = glm::normalize(glm::cross(axis, Vec3(0.0f, 0.0f, 1.0f)));
  auto normal_at = [&](float theta) { return std::cos(theta) * axis + std::sin(theta) * side; };
  expect_near(hemisphere_ambient(a, b, axis, normal_at(0.0f)), a, 1e-6f);
  expect_near(hemisphere_ambient(a, b, axis, normal_at(kPi / 2)), 0.5f * (a + b), 1e-6f);
  expect_near(hemisphere_ambient(a, b, axis, normal_at(kPi)), b, 1e-6f);
  // The seed's piecewise form in between: sin(pi/6)/2 = 1/4.
  expect_near(hemisphere_ambient(a, b, axis, normal_at(kPi / 6)), 0.75f * a + 0.25f * b, 1e-6f);
  expect_near(hemisphere_ambient(a, b, axis, normal_at(5 * kPi / 6)), 0.25f * a + 0.75f * b, 1e-6f);
  // Continuous across pi/2.
  expect_near(hemisphere_ambient(a, b, axis, normal_at(kPi / 2 - 1e-3f)),
              hemisphere_ambient(a, b, axis, normal_at(kPi / 2 + 1e-3f)), 1e-3f);

  Ambient amb;
  amb.kind = AmbientKind::kNone;
  expect_near(ambient_light(amb, Vec3(0.0f), axis), Vec3(0.0f), 0.0f);
  amb.kind = AmbientKind::kConstant;
  amb.constant = Vec3(0.3f);
  expect_near(ambient_light(amb, Vec3(0.0f), -axis), Vec3(0.3f), 0.0f);
}

// A floor quad at y = 0 with the material under test, seen from (-1, 1, 0) toward the origin
// (e.n = 1/sqrt 2), lit from (2, 3, 1) (so h.n differs from the OCR's h.l), background reflected.
struct MaterialFixture {
  std::unique_ptr<Scene> scene = make_empty_scene();
  Vec3 la{0.1f, 0.2f, 0.3f};
  Vec3 le{0.9f, 0.8f, 0.7f};
  Vec3 bg{0.3f, 0.5f, 0.7f};
  float n = 8.0f;

  explicit MaterialFixture(const Material& m, bool occluder = false) {
    scene->materials.push_back(m);
    scene->materials.push_back(make_material(MaterialClass::kDiffuse));
    add_horizontal_quad(scene->geometry, 0.0f, 10.0f, 0);
    if (occluder) add_sphere(scene->geometry, Vec3(4.0f / 3, 2.0f, 2.0f / 3), 0.3f, 1);
    scene->ambient.kind = AmbientKind::kConstant;
    scene->ambient.constant = la;
    scene->lights.push_back(Light{Vec3(2.0f, 3.0f, 1.0f), le, 0.0f});
    scene->settings.background = bg;
    finalize_scene(*scene);
  }
  Vec3 render() const {
    Ray r;
    r.org = Vec3(-1.0f, 1.0f, 0.0f);
    r.dir = glm::normalize(Vec3(1.0f, -1.0f, 0.0f));
    return trace_radiance(*scene, r, 0, Vec3(1.0f), nullptr);
  }
  Vec3 l() const { return glm::normalize(Vec3(2.0f, 3.0f, 1.0f)); }
  float nl() const { return l().y; }
  // Blinn-Phong (h.n)^N with h = normalize(e + l).
  float highlight() const {
    const Vec3 h = glm::normalize(glm::normalize(Vec3(-1.0f, 1.0f, 0.0f)) + l());
    return std::pow(h.y, n);
  }
};

TEST(MaterialClass, DiffuseIsEquationOneWithoutSpecularTerms) {
  Material m = make_material(MaterialClass::kDiffuse);
  m.kd = Vec3(0.5f, 0.6f, 0.7f);
  MaterialFixture f(m);
  expect_near(f.render(), m.kd * (f.la + f.le * f.nl()), 1e-5f);
  // In shadow only the ambient term remains (s = 0).
  MaterialFixture shadowed(m, /*occluder=*/true);
  expect_near(shadowed.render(), m.kd * f.la, 1e-5f);
}

TEST(MaterialClass, DiffuseUnderHemisphereAmbient) {
  Material m = make_material(MaterialClass::kDiffuse);
  m.kd = Vec3(0.5f);
  MaterialFixture f(m, /*occluder=*/true);
  f.scene->ambient.kind = AmbientKind::kHemisphere;
  f.scene->ambient.a = Vec3(0.4f, 0.3f, 0.2f);
  f.scene->ambient.b = Vec3(0.0f, 0.1f, 0.6f);
  f.scene->ambient.axis = Vec3(1.0f, 0.0f, 0.0f);  // theta = pi/2 for the floor's normal
  expect_near(f.render(), m.kd * 0.5f * (f.scene->ambient.a + f.scene->ambient.b), 1e-5f);
}

TEST(MaterialClass, MetalHasHighlightAndMirrorTermsWithKhEqualKs) {
  Material m = make_material(MaterialClass::kMetal);
  m.ks = Vec3(0.8f, 0.6f, 0.4f);
  m.kd = Vec3(0.9f);  // must be ignored: k_d = 0 for metal
  m.phong_exponent = 8.0f;
  MaterialFixture f(m);
  expect_near(f.render(), f.le * m.ks * f.highlight() + m.ks * f.bg, 1e-5f);
}

TEST(MaterialClass, DielectricReflectsSchlickAndAttenuatesTransmission) {
  Material m = make_material(MaterialClass::kDielectric);
  m.ior = 1.5f;
  m.kh = Vec3(0.5f);
  m.phong_exponent = 8.0f;
  m.extinction = Vec3(1.0f);  // the transmitted ray never leaves: exp(-kappa inf) = 0
  MaterialFixture f(m);
  const float ks = 0.04f + 0.96f * std::pow(1.0f - std::sqrt(0.5f), 5.0f);
  expect_near(f.render(), f.le * m.kh * f.highlight() + ks * f.bg, 1e-5f);
  // Without extinction the transmitted ray sees the background too: k_s + k_t = 1.
  f.scene->materials[0].extinction = Vec3(0.0f);
  expect_near(f.render(), f.le * m.kh * f.highlight() + f.bg, 1e-5f);
}

TEST(MaterialClass, PolishedIsEquationTwo) {
  Material m = make_material(MaterialClass::kPolished);
  m.kd = Vec3(0.6f, 0.3f, 0.2f);
  m.r0 = Vec3(0.05f, 0.1f, 0.2f);
  m.kh = Vec3(0.4f);
  m.phong_exponent = 8.0f;
  MaterialFixture f(m);
  const float en = std::sqrt(0.5f), nl = f.nl();
  const Vec3 ks = m.r0 + (Vec3(1.0f) - m.r0) * std::pow(1.0f - en, 5.0f);
  const Vec3 want =
      m.kd * f.la * (Vec3(1.0f) - ks) +
      m.kd * f.le * (1.0f - std::pow(1.0f - en, 5.0f)) * (1.0f - std::pow(1.0f - nl, 5.0f)) +
      m.kh * f.le * f.highlight() + ks * f.bg;
  expect_near(f.render(), want, 1e-5f);
}

TEST(MaterialClass, DepthLimitStopsRecursion) {
  Material m = make_material(MaterialClass::kMetal);
  m.ks = Vec3(0.5f);
  MaterialFixture f(m);
  f.scene->lights.clear();
  finalize_scene(*f.scene);
  expect_near(f.render(), m.ks * f.bg, 1e-6f);
  f.scene->settings.max_depth = 0;
  expect_near(f.render(), Vec3(0.0f), 0.0f);
}

// A dielectric slab [-d, 0] over a diffuse floor lit only by ambient W = kd la, viewed straight
// down. With ior 1 (R0 = 0) the result is exp(-kappa d) W; with ior 1.5 it is the closed-form sum
// of all internal reflections.
struct SlabFixture {
  std::unique_ptr<Scene> scene = make_empty_scene();
  SlabFixture(float thickness, float ior, Vec3 kappa) {
    Material glass = make_material(MaterialClass::kDielectric);
    glass.ior = ior;
    glass.extinction = kappa;
    glass.kh = Vec3(0.0f);
    Material floor = make_material(MaterialClass::kDiffuse);
    floor.kd = Vec3(0.5f);
    scene->materials = {glass, floor};
    add_horizontal_quad(scene->geometry, 0.0f, 50.0f, 0, /*up=*/true);
    add_horizontal_quad(scene->geometry, -thickness, 50.0f, 0, /*up=*/false);
    add_horizontal_quad(scene->geometry, -thickness - 1.0f, 50.0f, 1, /*up=*/true);
    scene->ambient.kind = AmbientKind::kConstant;
    scene->ambient.constant = Vec3(0.8f);
    scene->settings.background = Vec3(0.25f, 0.5f, 1.0f);
    scene->settings.min_contribution = 1e-12f;
    finalize_scene(*scene);
  }
  Vec3 render() const {
    Ray r;
    r.org = Vec3(0.3f, 5.0f, -0.2f);
    r.dir = Vec3(0.0f, -1.0f, 0.0f);
    return trace_radiance(*scene, r, 0, Vec3(1.0f), nullptr);
  }
};

TEST(Dielectric, AttenuationFollowsExpMinusKappaT) {
  const Vec3 w(0.5f * 0.8f);
  for (float d : {0.1f, 1.0f, 3.0f}) {
    for (float k : {0.0f, 0.5f, 2.0f}) {
      const Vec3 kappa(k, 0.5f * k, 0.0f);
      SlabFixture f(d, 1.0f, kappa);
      const Vec3 want = Vec3(std::exp(-kappa.x * d), std::exp(-kappa.y * d), 1.0f) * w;
      const Vec3 got = f.render();
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-5f * want[c] + 1e-7f);
    }
  }
}

TEST(Dielectric, SlabMatchesClosedFormWithInternalReflections) {
  const float d = 0.7f, r0 = 0.04f, t = 1.0f - r0;
  const Vec3 kappa(0.3f, 1.0f, 0.0f), w(0.4f), bg(0.25f, 0.5f, 1.0f);
  SlabFixture f(d, 1.5f, kappa);
  const Vec3 got = f.render();
  for (int c = 0; c < 3; ++c) {
    const float a = std::exp(-kappa[c] * d);
    // Looking down inside: L_d = a (R0 L_u + T W), looking up inside: L_u = a (R0 L_d + T bg).
    const float ld = (a * a * r0 * t * bg[c] + a * t * w[c]) / (1.0f - a * a * r0 * r0);
    EXPECT_NEAR(got[c], r0 * bg[c] + t * ld, 1e-5f) << "channel " << c;
  }
}

// Looking up at a glass ceiling from inside: beyond the critical angle all light is reflected
// (back down to the background); before it, part of the lit wall above shows through.
TEST(Dielectric, TotalInternalReflectionHidesTheOutside) {
  auto scene = make_empty_scene();
  Material glass = make_material(MaterialClass::kDielectric);
  glass.ior = 1.5f;
  glass.kh = Vec3(0.0f);
  Material wall = make_material(MaterialClass::kDiffuse);
  wall.kd = Vec3(1.0f);
  scene->materials = {glass, wall};
  add_horizontal_quad(scene->geometry, 0.0f, 20.0f, 0, /*up=*/true);
  add_horizontal_quad(scene->geometry, 2.0f, 20.0f, 1, /*up=*/false);
  scene->ambient.kind = AmbientKind::kConstant;
  scene->ambient.constant = Vec3(0.9f);
  const Vec3 bg(0.1f, 0.2f, 0.3f);
  scene->settings.background = bg;
  finalize_scene(*scene);
  auto look_up = [&](float angle) {
    Ray r;
    r.org = Vec3(0.0f, -1.0f, 0.0f);
    r.dir = Vec3(std::sin(angle), std::cos(angle), 0.0f);
    return trace_radiance(*scene, r, 0, Vec3(1.0f), nullptr);
  };
  expect_near(look_up(glm::radians(60.0f)), bg, 1e-6f);
  const float a = glm::radians(30.0f);
  const float cos_t = std::sqrt(1.0f - 2.25f * std::sin(a) * std::sin(a));
  const float ks = 0.04f + 0.96f * std::pow(1.0f - cos_t, 5.0f);
  expect_near(look_up(a), ks * bg + (1.0f - ks) * Vec3(0.9f), 1e-5f);
}

// A scene of mutually reflecting glass and metal spheres; the image with a tiny pruning threshold
// equals the unpruned one within 1e-3 everywhere, while a coarse threshold visibly differs.
TEST(Pruning, TinyThresholdChangesNothingVisible) {
  auto scene = make_empty_scene();
  Material glass = make_material(MaterialClass::kDielectric);
  glass.kh = Vec3(0.3f);
  glass.extinction = Vec3(0.1f, 0.2f, 0.3f);
  Material metal = make_material(MaterialClass::kMetal);
  metal.ks = Vec3(0.9f, 0.8f, 0.6f);
  Material floor = make_material(MaterialClass::kPolished);
  floor.kd = Vec3(0.4f, 0.5f, 0.3f);
  scene->materials = {glass, metal, floor};
  add_sphere(scene->geometry, Vec3(-0.6f, 0.5f, 0.0f), 0.5f, 0);
  add_sphere(scene->geometry, Vec3(0.6f, 0.5f, 0.0f), 0.5f, 1);
  add_sphere(scene->geometry, Vec3(0.0f, 0.5f, -1.1f), 0.5f, 1);
  add_horizontal_quad(scene->geometry, 0.0f, 5.0f, 2);
  scene->lights.push_back(Light{Vec3(2.0f, 4.0f, 3.0f), Vec3(1.0f), 0.0f});
  scene->ambient.kind = AmbientKind::kHemisphere;
  scene->settings.background = Vec3(0.5f, 0.6f, 0.8f);
  finalize_scene(*scene);
  Camera cam;
  cam.eye = Vec3(0.0f, 1.5f, 3.5f);
  cam.look = Vec3(0.0f, 0.4f, 0.0f);
  const CameraBasis basis = make_camera_basis(cam, 48, 36);
  auto max_diff = [&](float threshold) {
    float worst = 0.0f;
    for (int y = 0; y < 36; ++y)
      for (int x = 0; x < 48; ++x) {
        const Ray r = camera_ray(basis, x + 0.5f, y + 0.5f);
        scene->settings.min_contribution = 1e-9f;
        const Vec3 full = trace_radiance(*scene, r, 0, Vec3(1.0f), nullptr);
        scene->settings.min_contribution = threshold;
        const Vec3 pruned = trace_radiance(*scene, r, 0, Vec3(1.0f), nullptr);
        worst = std::max(worst, glm::length(full - pruned));
      }
    return worst;
  };
  EXPECT_LT(max_diff(1e-4f), 1e-3f);
  EXPECT_GT(max_diff(0.5f), 1e-2f);  // the comparison has power
}

}  // namespace
}  // namespace frameless
