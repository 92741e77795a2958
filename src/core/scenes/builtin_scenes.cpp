// Built-in scenes: "default", "cornell", "balls", "spheres:N[:SEED]", "soup:N[:SEED]" (builtin_soup.cpp), "bunny" (volumes: builtin_volume.cpp).
#include "core/scenes/builtin_scenes.h"

#include <charconv>
#include <cmath>
#include <sys/stat.h>

#include "core/base/rng.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/scene_load.h"

namespace frameless {

Material diffuse(const char* name, Vec3 kd) {
  Material m;
  m.name = name;
  m.cls = MaterialClass::kDiffuse;
  m.kd = kd;
  return m;
}

Material metal(const char* name, Vec3 ks, float phong) {
  Material m;
  m.name = name;
  m.cls = MaterialClass::kMetal;
  m.kd = Vec3(0.0f);
  m.ks = ks;
  m.kh = ks;
  m.phong_exponent = phong;
  return m;
}

Material dielectric(const char* name, float ior, Vec3 extinction) {
  Material m;
  m.name = name;
  m.cls = MaterialClass::kDielectric;
  m.kd = Vec3(0.0f);
  m.ior = ior;
  m.extinction = extinction;
  m.kh = Vec3(1.0f);
  m.phong_exponent = 300.0f;
  return m;
}

Material polished(const char* name, Vec3 kd, float r0) {
  Material m;
  m.name = name;
  m.cls = MaterialClass::kPolished;
  m.kd = kd;
  m.r0 = Vec3(r0);
  m.kh = Vec3(0.8f);
  m.phong_exponent = 120.0f;
  return m;
}

namespace {

// The project's face: one large sphere of each material class in an open room (floor, back
// and left walls), a few small spheres and a box, one light and the hemisphere ambient.
std::unique_ptr<Scene> make_default() {
  auto s = std::make_unique<Scene>();
  s->name = "default";
  const uint16_t floor = add_material(*s, diffuse("floor", Vec3(0.58f, 0.56f, 0.52f)));
  const uint16_t wall = add_material(*s, diffuse("wall", Vec3(0.62f, 0.64f, 0.70f)));
  const uint16_t clay = add_material(*s, diffuse("clay", Vec3(0.80f, 0.28f, 0.18f)));
  const uint16_t gold = add_material(*s, metal("gold", Vec3(0.95f, 0.74f, 0.36f), 200.0f));
  const uint16_t glass = add_material(*s, dielectric("glass", 1.5f, Vec3(0.06f, 0.02f, 0.04f)));
  const uint16_t lacquer = add_material(*s, polished("lacquer", Vec3(0.10f, 0.22f, 0.62f), 0.05f));
  const uint16_t jade = add_material(*s, polished("jade", Vec3(0.18f, 0.55f, 0.30f), 0.04f));
  const uint16_t chrome = add_material(*s, metal("chrome", Vec3(0.85f), 400.0f));
  const uint16_t ivory = add_material(*s, diffuse("ivory", Vec3(0.85f, 0.82f, 0.70f)));

  add_quad(*s, Vec3(0.0f, 0.0f, 0.0f), Vec3(0, 1, 0), 16.0f, floor);
  add_quad(*s, Vec3(0.0f, 4.0f, -4.0f), Vec3(0, 0, 1), 16.0f, wall);
  add_quad(*s, Vec3(-6.0f, 4.0f, 0.0f), Vec3(1, 0, 0), 16.0f, wall);

  const float r = 0.8f;
  add_sphere(*s, Vec3(-2.7f, r, 0.0f), r, clay);
  add_sphere(*s, Vec3(-0.9f, r, -0.4f), r, gold);
  add_sphere(*s, Vec3(0.9f, r, 0.0f), r, glass);
  add_sphere(*s, Vec3(2.7f, r, -0.4f), r, lacquer);
  add_sphere(*s, Vec3(-1.6f, 0.3f, 1.5f), 0.3f, chrome);
  add_sphere(*s, Vec3(0.0f, 0.25f, 1.8f), 0.25f, jade);
  add_sphere(*s, Vec3(1.7f, 0.3f, 1.5f), 0.3f, ivory);
  add_box(*s, Vec3(-4.6f, 0.0f, -2.6f), Vec3(-3.4f, 1.6f, -1.4f), ivory);

  s->lights.push_back(Light{Vec3(3.0f, 6.5f, 5.0f), Vec3(0.9f, 0.88f, 0.82f), 0.3f});
  s->ambient = default_hemisphere_ambient();
  s->camera.eye = Vec3(0.4f, 2.4f, 7.8f);
  s->camera.look = Vec3(0.0f, 0.7f, 0.0f);
  s->camera.up = Vec3(0.0f, 1.0f, 0.0f);
  s->camera.fov_deg = 45.0f;
  // A muted sky, so metal and glass reflect something where the room is open.
  s->settings.background = Vec3(0.30f, 0.36f, 0.46f);
  return s;
}

Result<uint64_t> parse_count(std::string_view text, const std::string& spec, const char* what) {
  uint64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size())
    return Error{spec + ": " + what + " '" + std::string(text) + "' is not a non-negative integer"};
  return v;
}

}  // namespace

void frame_random_scene(Scene& s, uint64_t seed) {
  Vec3 lo, hi;
  geometry_bounds(s.geometry, lo, hi);
  s.camera = frame_camera(lo, hi, s.settings.width, s.settings.height);
  const float extent = glm::length(hi - lo);
  s.lights.push_back(Light{0.5f * (lo + hi) + extent * Vec3(0.6f, 1.2f, 0.9f), Vec3(0.9f), 0.0f});
  s.ambient = default_hemisphere_ambient();
  s.settings.seed = seed;
}

namespace {

// "NAME:N[:SEED]" after its prefix of `skip` characters: N in 1..max, SEED 1 unless given.
struct CountAndSeed {
  uint64_t n = 0, seed = 1;
};
Result<CountAndSeed> parse_count_and_seed(const std::string& spec, size_t skip, uint64_t max) {
  std::string_view rest = std::string_view(spec).substr(skip);
  const size_t colon = rest.find(':');
  auto n = parse_count(rest.substr(0, colon), spec, "N");
  if (!n) return n.error();
  CountAndSeed out{*n, 1};
  if (colon != std::string_view::npos) {
    auto sd = parse_count(rest.substr(colon + 1), spec, "SEED");
    if (!sd) return sd.error();
    out.seed = *sd;
  }
  if (out.n < 1 || out.n > max) return Error{spec + ": N must be in 1.." + std::to_string(max)};
  return out;
}

// N random spheres in a cube whose side grows as cbrt(N), so density (and the picture) stays
// alike for any N. Flat arrays reserved up front: 18 bytes per sphere before the BVH.
Result<std::unique_ptr<Scene>> make_spheres(const std::string& spec) {
  auto parsed = parse_count_and_seed(spec, 8, kMaxRandomSpheres);
  if (!parsed) return parsed.error();
  const uint64_t seed = parsed->seed, count = parsed->n;
  auto s = std::make_unique<Scene>();
  s->name = spec;
  uint16_t mats[8];
  mats[0] = add_material(*s, diffuse("red", Vec3(0.8f, 0.25f, 0.2f)));
  mats[1] = add_material(*s, diffuse("green", Vec3(0.25f, 0.7f, 0.3f)));
  mats[2] = add_material(*s, diffuse("blue", Vec3(0.2f, 0.35f, 0.8f)));
  mats[3] = add_material(*s, diffuse("white", Vec3(0.8f)));
  mats[4] = add_material(*s, polished("orange", Vec3(0.9f, 0.5f, 0.1f), 0.05f));
  mats[5] = add_material(*s, polished("violet", Vec3(0.5f, 0.25f, 0.7f), 0.05f));
  mats[6] = add_material(*s, metal("steel", Vec3(0.8f), 200.0f));
  mats[7] = add_material(*s, dielectric("glass", 1.5f, Vec3(0.0f)));
  const float side = std::cbrt(float(count));
  Geometry& g = s->geometry;
  // Exactly N each (no growth, no copies; the in-place sphere BVH build adds only its nodes).
  g.spheres.reserve(count);
  g.sphere_material.reserve(count);
  Rng rng(seed);
  for (uint64_t i = 0; i < count; ++i) {
    const float x = rng.next_float(), y = rng.next_float(), z = rng.next_float();
    const float r = 0.1f + 0.2f * rng.next_float();
    g.spheres.push_back(Sphere{side * (Vec3(x, y, z) - 0.5f), r});
    g.sphere_material.push_back(mats[rng.next_u32() & 7u]);
  }
  frame_random_scene(*s, seed);
  return s;
}

Result<std::unique_ptr<Scene>> make_bunny() {
  struct stat st;
  if (stat(kBunnyPath, &st) != 0) {
    std::string m = "bunny: ";  // appended: GCC 12 misreads an operator+ chain (-Warray-bounds)
    m += kBunnyPath;
    m += " not found: install Debian's glmark2-data (apt-get install glmark2-data)";
    return Error{m};
  }
  auto mesh = load_mesh(kBunnyPath);
  if (!mesh) return mesh.error();
  auto s = make_mesh_scene(std::move(*mesh), "bunny");
  s->materials[0] = polished("bunny", Vec3(0.78f, 0.74f, 0.66f), 0.04f);
  Vec3 lo, hi;
  geometry_bounds(s->geometry, lo, hi);
  const uint16_t floor = add_material(*s, diffuse("floor", Vec3(0.6f, 0.62f, 0.66f)));
  add_quad(*s, Vec3(0.5f * (lo.x + hi.x), lo.y, 0.5f * (lo.z + hi.z)), Vec3(0, 1, 0),
           8.0f * glm::length(hi - lo), floor);
  return s;
}

}  // namespace

Result<std::unique_ptr<Scene>> make_builtin_scene(const std::string& name) {
  Result<std::unique_ptr<Scene>> scene = Error{""};
  if (name == "default") scene = make_default();
  else if (name == "balls") scene = make_balls();
  else if (name == "bunny") scene = make_bunny();
  else if (name == "cornell") scene = make_cornell();
  else if (name == "showcase") return make_showcase();  // a JSON scene: already finalized
  else if (name == "teapot") return make_teapot();
  else if (name == "room") return make_room();
  else if (name == "office") return make_office();
  else if (name.rfind("spheres:", 0) == 0) scene = make_spheres(name);
  else if (name.rfind("soup:", 0) == 0) {
    auto parsed = parse_count_and_seed(name, 5, kMaxSoupTriangles);
    if (!parsed) return parsed.error();
    scene = make_soup(parsed->n, parsed->seed);
  }
  else if (name.rfind("volume:", 0) == 0) return make_volume_scene(name);
  else if (name == "sunflowers") return make_sunflowers();
  else if (name.rfind("sunflowers:", 0) == 0) {
    auto n = parse_count(std::string_view(name).substr(11), name, "plant count");
    if (!n) return n.error();
    if (*n < 1 || *n > kMaxSunflowers)
      return Error{name + ": plant count must be between 1 and " + std::to_string(kMaxSunflowers)};
    return make_sunflowers(*n);
  } else if (name.rfind("sunflowers-flat:", 0) == 0) {
    auto n = parse_count(std::string_view(name).substr(16), name, "plant count");
    if (!n) return n.error();
    if (*n < 1 || *n > kMaxFlatSunflowers)
      return Error{name + ": plant count must be between 1 and " + std::to_string(kMaxFlatSunflowers)};
    return make_sunflowers(*n, true);
  } else
    return Error{name + ": not a file with a known extension (" + scene_file_kinds() + ") nor a built-in "
                        "scene (default, cornell, showcase, balls, teapot, room, office, sunflowers[:N], "
                        "sunflowers-flat:N, spheres:N[:SEED], soup:N[:SEED], volume:KIND:N[:MODE], bunny)"};
  if (!scene) return scene;
  finalize_scene(**scene);
  return scene;
}

const char* builtin_scene_help() {
  return "Built-in scenes:\n"
         "  default            all four material classes in an open room, hemisphere ambient\n"
         "  cornell            the Cornell box: its published geometry and ceiling light, path traced\n"
         "  showcase           soft shadows, image and solid textures, a cut-out, a glTF model\n"
         "  balls              Parker's bouncing balls: physics, soft shadows, moving while you look\n"
         "  teapot             the Utah teapot's 32 Bezier patches, ray traced directly\n"
         "  room               figure 16: ~75,000 polygons, spline teapot, glass, textures\n"
         "  office             OpenRT's office: plug-in wood and marble, a lightfield in a bump-mapped\n"
         "                     mirror, the volume shader's phantom, glass, soft shadows\n"
         "  sunflowers[:N]     OpenRT's sunflower field: 10 plant kinds instanced N times (default\n"
         "                     46000: about a billion triangles), cut-out leaves, a low sun\n"
         "  sunflowers-flat:N  the same N plants as one plain mesh (~21,000 triangles each on average)\n"
         "  spheres:N[:SEED]   N random spheres, 1 <= N <= 35000000, seeded (default seed 1)\n"
         "  soup:N[:SEED]      N random overlapping triangles, 1 <= N <= 20000000, seeded\n"
         "  volume:KIND:N[:MODE]  a generated volume: KIND marschner-lobb, shepp-logan (N or\n"
         "                     NXxNYxNZ: a CT-like head) or sphere (a distance field), N voxels a side;\n"
         "                     MODE isosurface (default), direct (the volume shader) or mip\n"
         "  bunny              the Stanford bunny from Debian's glmark2-data\n"
         "Or a scene file (.json) or a mesh file (.obj, .ply).";
}

}  // namespace frameless
