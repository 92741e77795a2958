// The Cornell box (builtin "cornell"): the geometry the Cornell Program of Computer Graphics
// publishes ("Cornell Box Data", millimetres), its camera (35 mm focal length, 25 mm film:
// 39.3 degrees), diffuse walls and the ceiling light as an emissive quad set into the ceiling. The reflectances and
// the light's radiance are the RGB values renderers commonly derive from the measured spectra.
#include "core/scenes/builtin_scenes.h"

#include <cmath>

#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"

namespace frameless {
namespace {

// A planar quad a-b-c-d as two triangles.
void add_polygon(Scene& s, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, uint16_t material) {
  Geometry& g = s.geometry;
  const uint32_t v = uint32_t(g.positions.size());
  for (const Vec3& p : {a, b, c, d}) g.positions.push_back(p);
  if (!g.uvs.empty() || !g.normals.empty()) {  // keep per-vertex arrays one per position
    for (int k = 0; k < 4; ++k) {
      if (!g.uvs.empty()) g.uvs.push_back(Vec2(0.0f));
      if (!g.normals.empty()) g.normals.push_back(glm::normalize(glm::cross(b - a, c - a)));
    }
  }
  g.triangles.push_back(UVec3(v, v + 1, v + 2));
  g.triangles.push_back(UVec3(v, v + 2, v + 3));
  g.triangle_material.push_back(material);
  g.triangle_material.push_back(material);
}

// A block: its top face (as the data lists it, facing up) and four sides, each wound to face
// outwards (the irradiance volume tells inside from outside by the faces rays see).
void add_block(Scene& s, const Vec3 (&top)[4], uint16_t material) {
  add_polygon(s, top[0], top[1], top[2], top[3], material);
  const Vec3 centre = 0.25f * (top[0] + top[1] + top[2] + top[3]);
  for (int k = 0; k < 4; ++k) {
    const Vec3 a = top[k], b = top[(k + 1) % 4], a0(a.x, 0.0f, a.z), b0(b.x, 0.0f, b.z);
    if (glm::dot(glm::cross(a - a0, b - a0), a - centre) > 0.0f)
      add_polygon(s, a0, a, b, b0, material);
    else
      add_polygon(s, b0, b, a, a0, material);
  }
}

}  // namespace

std::unique_ptr<Scene> make_cornell() {
  auto s = std::make_unique<Scene>();
  s->name = "cornell";
  const uint16_t white = add_material(*s, diffuse("white", Vec3(0.725f, 0.71f, 0.68f)));
  const uint16_t red = add_material(*s, diffuse("red", Vec3(0.63f, 0.065f, 0.05f)));
  const uint16_t green = add_material(*s, diffuse("green", Vec3(0.14f, 0.45f, 0.091f)));
  Material lamp = diffuse("light", Vec3(0.78f));
  lamp.emission = Vec3(17.0f, 12.0f, 4.0f);
  const uint16_t light = add_material(*s, lamp);

  add_polygon(*s, {552.8f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 559.2f}, {549.6f, 0.0f, 559.2f}, white);
  // The ceiling around the light's opening, in four strips: the light fills the opening, in the
  // ceiling's plane, so no gap between them catches light from its back side.
  const float cy = 548.8f;
  add_polygon(*s, {556.0f, cy, 0.0f}, {556.0f, cy, 227.0f}, {0.0f, cy, 227.0f}, {0.0f, cy, 0.0f}, white);
  add_polygon(*s, {556.0f, cy, 332.0f}, {556.0f, cy, 559.2f}, {0.0f, cy, 559.2f}, {0.0f, cy, 332.0f}, white);
  add_polygon(*s, {556.0f, cy, 227.0f}, {556.0f, cy, 332.0f}, {343.0f, cy, 332.0f}, {343.0f, cy, 227.0f}, white);
  add_polygon(*s, {213.0f, cy, 227.0f}, {213.0f, cy, 332.0f}, {0.0f, cy, 332.0f}, {0.0f, cy, 227.0f}, white);
  add_polygon(*s, {549.6f, 0.0f, 559.2f}, {0.0f, 0.0f, 559.2f}, {0.0f, 548.8f, 559.2f}, {556.0f, 548.8f, 559.2f}, white);
  add_polygon(*s, {0.0f, 0.0f, 559.2f}, {0.0f, 0.0f, 0.0f}, {0.0f, 548.8f, 0.0f}, {0.0f, 548.8f, 559.2f}, green);
  add_polygon(*s, {552.8f, 0.0f, 0.0f}, {549.6f, 0.0f, 559.2f}, {556.0f, 548.8f, 559.2f}, {556.0f, 548.8f, 0.0f}, red);
  add_polygon(*s, {343.0f, cy, 227.0f}, {343.0f, cy, 332.0f}, {213.0f, cy, 332.0f}, {213.0f, cy, 227.0f}, light);
  const Vec3 short_block[4] = {{130.0f, 165.0f, 65.0f}, {82.0f, 165.0f, 225.0f}, {240.0f, 165.0f, 272.0f}, {290.0f, 165.0f, 114.0f}};
  const Vec3 tall_block[4] = {{423.0f, 330.0f, 247.0f}, {265.0f, 330.0f, 296.0f}, {314.0f, 330.0f, 456.0f}, {472.0f, 330.0f, 406.0f}};
  add_block(*s, short_block, white);
  add_block(*s, tall_block, white);

  s->camera.eye = Vec3(278.0f, 273.0f, -800.0f);
  s->camera.look = Vec3(278.0f, 273.0f, 0.0f);
  s->camera.up = Vec3(0.0f, 1.0f, 0.0f);
  s->camera.fov_deg = float(2.0 * std::atan(12.5 / 35.0) * 180.0 / 3.14159265358979323846);
  s->settings.width = 512;
  s->settings.height = 512;
  s->settings.background = Vec3(0.0f);
  s->ambient.kind = AmbientKind::kNone;
  return s;
}

}  // namespace frameless
