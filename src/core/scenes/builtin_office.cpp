// The built-in "office" (issue 28; OpenRT's figure 1, Wald et al. 2003): objects that carry their
// own shading side by side. A room with a desk and two chairs; wood and marble from plug-in
// shaders (examples/shaders, this build's); a bump-mapped mirror on the back wall
// that shows a lightfield object (a sculpture baked into two light slabs when the scene loads,
// one facing the camera and one facing its image in the mirror); the Shepp-Logan phantom through
// the volume shader, seen in the mirror and casting a transparent shadow; a glass vase; soft
// shadows from two spherical lights. The room is JSON kept in the binary; the slabs are added here.
#include <cmath>

#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/builtin_scenes.h"
#include "core/shading/lightfield_bake.h"

namespace frameless {
namespace {

constexpr const char* kOfficeJson = R"json({
  "camera": { "eye": [2.75, 1.75, 2.9], "look": [-0.9, 0.95, -2.4], "fov": 52 },
  "settings": { "shadows": "soft", "background": [0.05, 0.05, 0.06], "width": 960, "height": 600 },
  "ambient": { "type": "hemisphere", "a": [0.2, 0.2, 0.21], "b": [0.07, 0.06, 0.05] },
  "lights": [
    { "type": "spherical", "position": [0.6, 2.75, -0.6], "color": [0.62, 0.58, 0.52], "radius": 0.25 },
    { "type": "spherical", "position": [-2.4, 2.75, 1.2], "color": [0.38, 0.4, 0.45], "radius": 0.25 }
  ],
  "textures": {
    "ripples": { "type": "image", "file": "glmark2/textures/asteroid-height-map.png", "srgb": false,
                 "uv_scale": [2, 1.5] }
  },
  "materials": {
    "marble": { "shader": "marble", "params": { "frequency": 1.3, "amplitude": 5, "polish": 0.25 } },
    "wood": { "shader": "wood", "params": { "rings": 9, "distortion": 0.8, "grain": 2.5, "varnish": 0.2,
                                            "center": [0.8, 0, -4] } },
    "dark wood": { "shader": "wood", "params": { "light": [0.42, 0.25, 0.13], "dark": [0.22, 0.11, 0.05],
                                                 "rings": 14, "varnish": 0.1, "center": [-3, 0, 0.5] } },
    "plaster": { "class": "diffuse", "kd": [0.72, 0.7, 0.66] },
    "ceiling": { "class": "diffuse", "kd": [0.8, 0.8, 0.8] },
    "steel": { "class": "metal", "ks": [0.62, 0.63, 0.66], "phong_exponent": 120 },
    "mirror": { "class": "metal", "ks": [0.9, 0.9, 0.92], "phong_exponent": 5000,
                "bump_texture": "ripples", "bump_scale": 0.08 },
    "frame": { "class": "polished", "kd": [0.12, 0.1, 0.09], "r0": 0.04, "kh": 0.3, "phong_exponent": 80 },
    "glass": { "class": "dielectric", "ior": 1.5, "extinction": [0.3, 0.06, 0.12] },
    "stand": { "class": "polished", "kd": [0.2, 0.22, 0.25], "r0": 0.04, "kh": 0.2, "phong_exponent": 60 }
  },
  "objects": [
    { "type": "box", "min": [-4, -0.1, -4], "max": [4, 0, 4], "material": "marble" },
    { "type": "box", "min": [-4, 3, -4], "max": [4, 3.1, 4], "material": "ceiling" },
    { "type": "box", "min": [-4.1, 0, -4.1], "max": [4.1, 3, -4], "material": "plaster" },
    { "type": "box", "min": [-4.1, 0, -4], "max": [-4, 3, 4], "material": "dark wood" },
    { "type": "box", "min": [4, 0, -4], "max": [4.1, 3, 4], "material": "plaster" },
    { "type": "box", "min": [-2.75, 0.55, -4.0], "max": [-0.45, 2.55, -3.96], "material": "frame" },
    { "type": "triangles", "material": "mirror",
      "vertices": [[-2.65, 0.65, -3.95], [-0.55, 0.65, -3.95], [-0.55, 2.45, -3.95], [-2.65, 2.45, -3.95]],
      "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]], "indices": [[0, 1, 2], [0, 2, 3]] },

    { "type": "box", "min": [-0.2, 0.72, -3.2], "max": [2.0, 0.78, -2.1], "material": "wood" },
    { "type": "box", "min": [-0.15, 0, -3.15], "max": [-0.07, 0.72, -3.07], "material": "wood" },
    { "type": "box", "min": [1.87, 0, -3.15], "max": [1.95, 0.72, -3.07], "material": "wood" },
    { "type": "box", "min": [-0.15, 0, -2.23], "max": [-0.07, 0.72, -2.15], "material": "wood" },
    { "type": "box", "min": [1.87, 0, -2.23], "max": [1.95, 0.72, -2.15], "material": "wood" },
    { "type": "box", "min": [-0.1, 0.2, -3.15], "max": [1.9, 0.72, -3.12], "material": "wood" },

    { "type": "box", "min": [0.45, 0.44, -2.05], "max": [0.95, 0.48, -1.55], "material": "dark wood" },
    { "type": "box", "min": [0.45, 0.48, -1.6], "max": [0.95, 1.0, -1.55], "material": "dark wood" },
    { "type": "box", "min": [0.47, 0, -2.03], "max": [0.51, 0.44, -1.99], "material": "steel" },
    { "type": "box", "min": [0.89, 0, -2.03], "max": [0.93, 0.44, -1.99], "material": "steel" },
    { "type": "box", "min": [0.47, 0, -1.61], "max": [0.51, 0.44, -1.57], "material": "steel" },
    { "type": "box", "min": [0.89, 0, -1.61], "max": [0.93, 0.44, -1.57], "material": "steel" },

    { "type": "box", "min": [2.5, 0.44, -1.3], "max": [3.0, 0.48, -0.8], "material": "dark wood" },
    { "type": "box", "min": [2.95, 0.48, -1.3], "max": [3.0, 1.0, -0.8], "material": "dark wood" },
    { "type": "box", "min": [2.52, 0, -1.28], "max": [2.56, 0.44, -1.24], "material": "steel" },
    { "type": "box", "min": [2.94, 0, -1.28], "max": [2.98, 0.44, -1.24], "material": "steel" },
    { "type": "box", "min": [2.52, 0, -0.86], "max": [2.56, 0.44, -0.82], "material": "steel" },
    { "type": "box", "min": [2.94, 0, -0.86], "max": [2.98, 0.44, -0.82], "material": "steel" },

    { "type": "sphere", "center": [1.55, 0.93, -2.55], "radius": 0.15, "material": "glass" },
    { "type": "sphere", "center": [1.2, 0.86, -2.8], "radius": 0.08, "material": "steel" },

    { "type": "box", "min": [-3.35, 0, -2.0], "max": [-2.55, 0.8, -1.2], "material": "stand" },
    { "type": "volume", "file": "volume:shepp-logan:96", "mode": "direct", "transfer": "ct-bone",
      "transform": { "translate": [-3.35, 0.8, -1.2], "rotate": { "axis": [1, 0, 0], "degrees": -90 }, "scale": 0.4 } },
    { "type": "box", "min": [-1.9, 0, -2.9], "max": [-1.3, 0.7, -2.3], "material": "stand" }
  ]
})json";

// The lightfield's sculpture, in its own frame (a unit-sized helix of coloured spheres on a
// golden base), lit by a light where the office's main light is relative to its plinth.
std::unique_ptr<Scene> sculpture() {
  auto s = std::make_unique<Scene>();
  s->name = "office sculpture";
  const uint16_t red = add_material(*s, polished("red", Vec3(0.75f, 0.12f, 0.08f), 0.05f));
  const uint16_t blue = add_material(*s, polished("blue", Vec3(0.1f, 0.25f, 0.8f), 0.05f));
  const uint16_t gold = add_material(*s, metal("gold", Vec3(0.95f, 0.74f, 0.35f), 300.0f));
  for (int k = 0; k < 28; ++k) {
    const float a = 0.55f * float(k), y = -0.35f + 0.032f * float(k);
    add_sphere(*s, Vec3(0.22f * std::cos(a), y, 0.22f * std::sin(a)), 0.07f, red);
    add_sphere(*s, Vec3(-0.22f * std::cos(a), y, -0.22f * std::sin(a)), 0.07f, blue);
  }
  add_sphere(*s, Vec3(0.0f, -0.05f, 0.0f), 0.09f, gold);
  add_box(*s, Vec3(-0.2f, -0.5f, -0.2f), Vec3(0.2f, -0.42f, 0.2f), gold);
  Light key;
  key.position = Vec3(2.2f, 2.3f, 2.0f);
  key.radius = 0.2f;
  key.color = Vec3(0.9f, 0.86f, 0.8f);
  s->lights.push_back(key);
  s->ambient = default_hemisphere_ambient();
  s->settings.shadows = ShadowMode::kSoft;
  finalize_scene(*s);
  return s;
}

// A slab around the sculpture (radius 0.62) whose z axis points towards `towards`.
Affine slab_facing(const Vec3& towards) {
  const Vec3 z = glm::normalize(towards);
  const Vec3 x = glm::normalize(glm::cross(Vec3(0.0f, 1.0f, 0.0f), z)), y = glm::cross(z, x);
  constexpr float kRadius = 0.62f;
  return Affine{glm::mat3(kRadius * x, kRadius * y, kRadius * z), Vec3(0.0f)};
}

}  // namespace

Result<std::unique_ptr<Scene>> make_office() {
  auto scene = load_embedded_scene(kOfficeJson, "office", {{"/usr/share/glmark2/textures", "glmark2-data"}});
  if (!scene) return scene;
  Scene& s = **scene;
  // The sculpture stands on the plinth in front of the mirror, seen directly and in the mirror:
  // one slab faces the camera, the other the camera's image behind the mirror (z = -3.95).
  const Vec3 at(-1.6f, 1.2f, -2.6f);
  Vec3 image = s.camera.eye;
  image.z = 2.0f * -3.95f - image.z;
  const auto model = sculpture();
  LightfieldBakeOptions o;
  o.nu = o.nv = 12;
  o.ns = o.nt = 96;
  o.spp = 1;
  for (const Vec3& viewer : {s.camera.eye, image}) {
    auto lf = std::make_shared<LightField>(bake_lightfield(*model, slab_facing(viewer - at), o, default_build_executor()));
    lf->source = "office sculpture (baked at load)";
    s.lightfields.push_back(place_lightfield(std::move(lf), Affine{glm::mat3(1.0f), at}));
  }
  refresh_see_through(s);  // the slabs make the scene see-through (no rebuild needed)
  return scene;
}

}  // namespace frameless
