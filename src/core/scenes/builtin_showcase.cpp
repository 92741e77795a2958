// The "showcase" built-in scene: soft shadows, image textures (PNG and JPEG), solid marble and
// wood, a cut-out texture casting letter-shaped shadows, a normal-mapped sphere and a textured
// glTF model. It is an ordinary JSON scene (docs/scene-format.md) kept in the binary; its files
// come from Debian's glmark2-data and assimp-testmodels.
#include <sys/stat.h>

#include "core/scenes/builtin_scenes.h"
#include "core/scenes/scene_load.h"

namespace frameless {
namespace {

constexpr const char* kShowcaseJson = R"json({
  "camera": { "eye": [0.4, 3.3, 8.6], "look": [0.1, 1.0, 0], "fov": 42 },
  "settings": { "shadows": "soft", "background": [0.42, 0.5, 0.62] },
  "ambient": { "type": "hemisphere", "a": [0.16, 0.19, 0.24], "b": [0.05, 0.04, 0.03] },
  "lights": [
    { "type": "spherical", "position": [-3.5, 7.5, 4.5], "color": [0.95, 0.9, 0.82], "radius": 0.9 }
  ],
  "textures": {
    "tiles": { "type": "image", "file": "assimp/models/OBJ/wal67ar_small.jpg", "uv_scale": [16, 16] },
    "crate": { "type": "image", "file": "glmark2/textures/crate-base.png" },
    "glyphs": { "type": "image", "file": "glmark2/textures/glyph-atlas.png", "srgb": false,
                "wrap": "clamp", "uv_scale": [0.99, 0.104], "uv_offset": [0, 0.668] },
    "bumps": { "type": "image", "file": "glmark2/textures/asteroid-normal-map-tangent.png",
               "srgb": false, "uv_scale": [2, 1] },
    "heights": { "type": "image", "file": "glmark2/textures/asteroid-height-map.png",
                 "srgb": false, "uv_scale": [2, 1] },
    "marble": { "type": "marble", "color_a": [0.92, 0.9, 0.86], "color_b": [0.25, 0.22, 0.24],
                "frequency": 2.2, "octaves": 6, "amplitude": 6 },
    "wood": { "type": "wood", "color_a": [0.62, 0.4, 0.2], "color_b": [0.33, 0.18, 0.08],
              "frequency": 6, "amplitude": 2, "space": "object" }
  },
  "materials": {
    "floor": { "class": "polished", "kd": 1, "kd_texture": "tiles", "r0": 0.02, "kh": 0.2,
               "phong_exponent": 60 },
    "wall": { "class": "diffuse", "kd": [0.7, 0.68, 0.64] },
    "crate": { "class": "diffuse", "kd": 1, "kd_texture": "crate" },
    "glyphs": { "class": "diffuse", "kd": [0.9, 0.55, 0.15], "alpha_texture": "glyphs",
                "alpha_cutoff": 0.5 },
    "marble": { "class": "polished", "kd": 1, "kd_texture": "marble", "r0": 0.04, "kh": 0.6,
                "phong_exponent": 200 },
    "wood": { "class": "polished", "kd": 1, "kd_texture": "wood", "r0": 0.03, "kh": 0.3,
              "phong_exponent": 40 },
    "rock": { "class": "diffuse", "kd": [0.55, 0.5, 0.46], "normal_texture": "bumps" },
    "stone": { "class": "diffuse", "kd": [0.5, 0.52, 0.55], "bump_texture": "heights",
               "bump_scale": 4 },
    "glass": { "class": "dielectric", "ior": 1.5, "extinction": [0.25, 0.08, 0.04] },
    "gold": { "class": "metal", "ks": [0.95, 0.74, 0.35], "phong_exponent": 400 }
  },
  "objects": [
    { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 40, "material": "floor" },
    { "type": "plane", "point": [0, 3.5, -3.2], "normal": [0, 0, 1], "size": 40, "material": "wall" },
    { "type": "box", "min": [-3.6, 0, -1.6], "max": [-2.2, 1.4, -0.2], "material": "crate" },
    { "type": "sphere", "center": [-0.9, 0.85, -0.9], "radius": 0.85, "material": "marble" },
    { "type": "sphere", "center": [1.9, 0.75, -0.2], "radius": 0.75, "material": "wood" },
    { "type": "sphere", "center": [0.45, 0.5, 1.1], "radius": 0.5, "material": "glass" },
    { "type": "sphere", "center": [-2.1, 0.45, 1.3], "radius": 0.45, "material": "rock" },
    { "type": "sphere", "center": [-1.0, 0.3, 2.4], "radius": 0.3, "material": "stone" },
    { "type": "sphere", "center": [3.2, 0.35, 1.5], "radius": 0.35, "material": "gold" },
    { "type": "triangles", "material": "glyphs",
      "vertices": [[-1.6, 2.0, -2.0], [2.6, 2.0, -2.0], [2.6, 2.55, -1.6], [-1.6, 2.55, -1.6]],
      "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]],
      "indices": [[0, 1, 2], [0, 2, 3]] },
    { "type": "mesh", "file": "assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf",
      "transform": { "translate": [3.3, 0.45, -1.6], "rotate": { "axis": [0, 1, 0], "degrees": 30 },
                     "scale": 0.9 } }
  ]
})json";

}  // namespace

Result<std::unique_ptr<Scene>> load_embedded_scene(const char* json, const char* name,
                                                   std::initializer_list<EmbeddedNeed> needs) {
  struct stat st;
  for (const EmbeddedNeed& n : needs)
    if (stat(n.dir, &st) != 0)
      return Error{std::string(name) + ": " + n.dir + " not found: install Debian's " + n.package};
  auto scene = parse_scene_json(json, name, "/usr/share");
  if (scene) scene.value()->name = name;
  return scene;
}

Result<std::unique_ptr<Scene>> make_showcase() {
  return load_embedded_scene(kShowcaseJson, "showcase",
                             {{"/usr/share/glmark2/textures", "glmark2-data"},
                              {"/usr/share/assimp/models", "assimp-testmodels"}});
}

}  // namespace frameless
