// The "teapot" and "room" built-in scenes: the Utah teapot's 32 Bézier patches ray traced
// directly (seed section 3.3, figure 14), and a room after figure 16 (about 75,000 polygons, the
// spline teapot, glass, image and solid textures, soft shadows). Both are ordinary JSON scenes
// (docs/scene-format.md) kept in the binary; their files come from Debian's povray-examples,
// glmark2-data and assimp-testmodels.
#include "core/scenes/builtin_scenes.h"

namespace frameless {
namespace {

constexpr const char* kTeapotJson = R"json({
  "camera": { "eye": [4.2, 3.6, 6.4], "look": [0.1, 1.0, 0], "fov": 38 },
  "settings": { "shadows": "soft", "background": [0.36, 0.42, 0.52] },
  "ambient": { "type": "hemisphere", "a": [0.18, 0.2, 0.24], "b": [0.05, 0.045, 0.04] },
  "lights": [
    { "type": "spherical", "position": [-4, 8, 5], "color": [0.95, 0.92, 0.86], "radius": 0.7 }
  ],
  "materials": {
    "porcelain": { "class": "polished", "kd": [0.78, 0.16, 0.12], "r0": 0.05, "kh": 0.9,
                   "phong_exponent": 180 },
    "floor": { "class": "diffuse", "kd": [0.6, 0.6, 0.62] }
  },
  "objects": [
    { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 40, "material": "floor" },
    { "type": "bezier", "file": "doc/povray/examples/advanced/teapot/teapot.inc", "depth": 4,
      "material": "porcelain",
      "transform": { "rotate": { "axis": [1, 0, 0], "degrees": -90 } } }
  ]
})json";

// Room of figure 16: walls with image textures, a wood floor and table (solid texture), a marble
// Stanford bunny (69,666 triangles), Wuson (3,732), a glass sphere and vase, and the spline teapot.
constexpr const char* kRoomJson = R"json({
  "camera": { "eye": [3.1, 1.75, 3.5], "look": [-0.4, 0.75, -1.0], "fov": 55 },
  "settings": { "shadows": "soft", "background": [0.1, 0.1, 0.12] },
  "ambient": { "type": "hemisphere", "a": [0.2, 0.19, 0.17], "b": [0.07, 0.065, 0.06] },
  "lights": [
    { "type": "spherical", "position": [0.6, 2.7, 0.8], "color": [0.85, 0.8, 0.72], "radius": 0.25 },
    { "type": "spherical", "position": [-2.8, 2.6, 2.6], "color": [0.35, 0.37, 0.42], "radius": 0.3 }
  ],
  "textures": {
    "tiles": { "type": "image", "file": "assimp/models/OBJ/wal67ar_small.jpg", "uv_scale": [3, 3] },
    "picture": { "type": "image", "file": "glmark2/textures/nasa1.png", "wrap": "clamp" },
    "grass": { "type": "image", "file": "glmark2/textures/terrain-grasslight-512.jpg",
               "uv_scale": [2, 2] },
    "wood": { "type": "wood", "color_a": [0.6, 0.38, 0.18], "color_b": [0.3, 0.16, 0.07],
              "frequency": 5, "amplitude": 2 },
    "marble": { "type": "marble", "color_a": [0.93, 0.91, 0.87], "color_b": [0.3, 0.27, 0.3],
                "frequency": 3, "octaves": 6, "amplitude": 6 }
  },
  "materials": {
    "floor": { "class": "polished", "kd": 1, "kd_texture": "wood", "r0": 0.03, "kh": 0.25,
               "phong_exponent": 50 },
    "wall": { "class": "diffuse", "kd": 1, "kd_texture": "tiles" },
    "plain": { "class": "diffuse", "kd": [0.75, 0.72, 0.66] },
    "picture": { "class": "diffuse", "kd": 1, "kd_texture": "picture" },
    "rug": { "class": "diffuse", "kd": 1, "kd_texture": "grass" },
    "table": { "class": "polished", "kd": 1, "kd_texture": "wood", "r0": 0.04, "kh": 0.4,
               "phong_exponent": 80 },
    "marble": { "class": "polished", "kd": 1, "kd_texture": "marble", "r0": 0.04, "kh": 0.6,
                "phong_exponent": 200 },
    "porcelain": { "class": "polished", "kd": [0.85, 0.85, 0.9], "r0": 0.05, "kh": 0.9,
                   "phong_exponent": 250 },
    "glass": { "class": "dielectric", "ior": 1.5, "extinction": [0.3, 0.1, 0.05] },
    "toy": { "class": "polished", "kd": [0.85, 0.6, 0.2], "r0": 0.04, "kh": 0.5, "phong_exponent": 90 }
  },
  "objects": [
    { "type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "size": 8, "material": "floor" },
    { "type": "plane", "point": [0, 3, 0], "normal": [0, -1, 0], "size": 8, "material": "plain" },
    { "type": "plane", "point": [0, 1.5, -4], "normal": [0, 0, 1], "size": 8, "material": "wall" },
    { "type": "plane", "point": [-4, 1.5, 0], "normal": [1, 0, 0], "size": 8, "material": "wall" },
    { "type": "plane", "point": [4, 1.5, 0], "normal": [-1, 0, 0], "size": 8, "material": "plain" },
    { "type": "plane", "point": [0, 1.5, 4], "normal": [0, 0, -1], "size": 8, "material": "plain" },
    { "type": "triangles", "material": "picture",
      "vertices": [[-1.4, 1.2, -3.98], [0.6, 1.2, -3.98], [0.6, 2.5, -3.98], [-1.4, 2.5, -3.98]],
      "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]], "indices": [[0, 1, 2], [0, 2, 3]] },
    { "type": "triangles", "material": "rug",
      "vertices": [[-2.2, 0.002, -2.6], [1.6, 0.002, -2.6], [1.6, 0.002, 0.6], [-2.2, 0.002, 0.6]],
      "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]], "indices": [[0, 2, 1], [0, 3, 2]] },
    { "type": "box", "min": [-1.0, 0.7, -1.6], "max": [0.8, 0.76, -0.5], "material": "table" },
    { "type": "box", "min": [-0.95, 0, -1.55], "max": [-0.85, 0.7, -1.45], "material": "table" },
    { "type": "box", "min": [0.65, 0, -1.55], "max": [0.75, 0.7, -1.45], "material": "table" },
    { "type": "box", "min": [-0.95, 0, -0.65], "max": [-0.85, 0.7, -0.55], "material": "table" },
    { "type": "box", "min": [0.65, 0, -0.65], "max": [0.75, 0.7, -0.55], "material": "table" },
    { "type": "bezier", "file": "doc/povray/examples/advanced/teapot/teapot.inc", "depth": 4,
      "material": "porcelain",
      "transform": { "translate": [-0.2, 0.76, -1.05], "rotate": { "axis": [1, 0, 0], "degrees": -90 },
                     "scale": 0.2 } },
    { "type": "sphere", "center": [0.5, 0.9, -0.8], "radius": 0.14, "material": "glass" },
    { "type": "box", "min": [-2.9, 0, -3.2], "max": [-2.1, 0.6, -2.4], "material": "marble" },
    { "type": "mesh", "file": "glmark2/models/bunny.obj", "material": "marble",
      "transform": { "translate": [-2.5, 1.25, -2.8], "rotate": { "axis": [0, 1, 0], "degrees": 30 },
                     "scale": 0.65 } },
    { "type": "mesh", "file": "assimp/models/OBJ/WusonOBJ.obj", "material": "toy",
      "transform": { "translate": [2.3, 0, -2.6], "rotate": { "axis": [0, 1, 0], "degrees": -50 },
                     "scale": 0.55 } },
    { "type": "sphere", "center": [1.6, 0.35, 0.2], "radius": 0.35, "material": "glass" }
  ]
})json";

constexpr EmbeddedNeed kPovray{"/usr/share/doc/povray/examples/advanced/teapot", "povray-examples"};

}  // namespace

Result<std::unique_ptr<Scene>> make_teapot() {
  return load_embedded_scene(kTeapotJson, "teapot", {kPovray});
}

Result<std::unique_ptr<Scene>> make_room() {
  return load_embedded_scene(kRoomJson, "room",
                             {kPovray, {"/usr/share/glmark2/models", "glmark2-data"},
                              {"/usr/share/assimp/models", "assimp-testmodels"}});
}

}  // namespace frameless
