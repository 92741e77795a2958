// JSON scene files (format: docs/scene-format.md). Strict: unknown keys, wrong types, non-finite
// or out-of-range numbers and unknown material names are errors that name the JSON field path.
#include <cmath>
#include <map>
#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/accel/instance.h"
#include "core/io/file_util.h"
#include "core/io/mesh_readers.h"
#include "core/io/scene_json.h"
#include "core/io/scene_json_environment.h"
#include "core/io/scene_json_materials.h"
#include "core/io/scene_json_motion.h"
#include "core/io/scene_json_patches.h"
#include "core/io/scene_json_lightfield.h"
#include "core/io/scene_json_volume.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"

namespace frameless {
namespace scene_json {

glm::mat4 parse_transform(const json& j, const std::string& f) {
  if (j.is_array()) {
    // 16 numbers, row-major (the matrix as written on paper).
    if (j.size() != 16) fail(f, "a matrix needs 16 numbers (row-major 4x4)");
    glm::mat4 m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        m[c][r] = float(get_number(j[size_t(r * 4 + c)], f + "[" + std::to_string(r * 4 + c) + "]"));
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
      fail(f, "last row must be 0 0 0 1 (affine transforms only)");
    if (std::fabs(glm::determinant(glm::mat3(m))) < 1e-30f) fail(f, "matrix is singular");
    return m;
  }
  require_object(j, f);
  check_keys(j, f, {"translate", "rotate", "scale"});
  glm::mat4 m(1.0f);
  // Applied to points as scale, then rotate, then translate: M = T R S.
  if (j.contains("translate")) m = glm::translate(m, get_vec3(j["translate"], f + ".translate"));
  if (j.contains("rotate")) {
    const json& r = j["rotate"];
    const json list = r.is_array() ? r : json::array({r});
    glm::mat4 rot(1.0f);
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string rf = r.is_array() ? f + ".rotate[" + std::to_string(i) + "]" : f + ".rotate";
      require_object(list[i], rf);
      check_keys(list[i], rf, {"axis", "degrees"});
      if (!list[i].contains("axis")) fail(rf + ".axis", "missing");
      if (!list[i].contains("degrees")) fail(rf + ".degrees", "missing");
      const Vec3 axis = get_unit(list[i]["axis"], rf + ".axis");
      // Left-multiplied so that the rotations apply to points in the order written.
      rot = glm::rotate(glm::mat4(1.0f), glm::radians(float(get_number(list[i]["degrees"], rf + ".degrees"))), axis) * rot;
    }
    m = m * rot;
  }
  if (j.contains("scale")) {
    const json& s = j["scale"];
    const Vec3 v = s.is_number() ? Vec3(float(get_number(s, f + ".scale"))) : get_vec3(s, f + ".scale");
    if (v.x == 0.0f || v.y == 0.0f || v.z == 0.0f) fail(f + ".scale", "must be non-zero");
    m = glm::scale(m, v);
  }
  return m;
}

}  // namespace scene_json

namespace {
using namespace scene_json;

void parse_camera(const json& j, Scene& s) {
  require_object(j, "camera");
  check_keys(j, "camera", {"eye", "look", "up", "fov"});
  if (j.contains("eye")) s.camera.eye = get_vec3(j["eye"], "camera.eye");
  if (j.contains("look")) s.camera.look = get_vec3(j["look"], "camera.look");
  if (j.contains("up")) s.camera.up = get_vec3(j["up"], "camera.up");
  if (j.contains("fov")) s.camera.fov_deg = get_float(j["fov"], "camera.fov", 1e-3, 179.0, "in (0, 179]");
  if (!camera_is_valid(s.camera))
    fail("camera", "degenerate camera (eye equals look, or up parallel to the view direction)");
}

void parse_settings(const json& j, RenderSettings& r) {
  require_object(j, "settings");
  check_keys(j, "settings", {"width", "height", "spp", "max_depth", "min_contribution", "background",
                             "seed", "shadows", "shadow_samples", "transparent_shadows", "accel",
                             "integrator", "environment", "igi"});
  if (j.contains("igi")) {
    const json& g = require_object(j["igi"], "settings.igi");
    check_keys(g, "settings.igi", {"paths", "interleave", "clamp"});
    if (g.contains("paths")) r.igi.paths = int(get_int(g["paths"], "settings.igi.paths", 1, 4096));
    if (g.contains("interleave")) r.igi.interleave = int(get_int(g["interleave"], "settings.igi.interleave", 1, 8));
    if (g.contains("clamp")) r.igi.clamp = get_float(g["clamp"], "settings.igi.clamp", 0.0, 1.0, "in [0, 1]");
  }
  if (j.contains("integrator") &&
      !parse_integrator(get_string(j["integrator"], "settings.integrator"), r.integrator))
    fail("settings.integrator", "unknown integrator '" + j["integrator"].get<std::string>() + "' (whitted, path or igi)");
  if (j.contains("accel") && !parse_accel_kind(get_string(j["accel"], "settings.accel"), r.accel))
    fail("settings.accel", "unknown structure '" + j["accel"].get<std::string>() + "' (bvh, grid or auto)");
  if (j.contains("shadows")) {
    const std::string m = get_string(j["shadows"], "settings.shadows");
    if (m == "soft") r.shadows = ShadowMode::kSoft;
    else if (m == "hard") r.shadows = ShadowMode::kHard;
    else if (m == "area") r.shadows = ShadowMode::kArea;
    else if (m == "beam") r.shadows = ShadowMode::kBeam;
    else fail("settings.shadows", "unknown mode '" + m + "' (soft, hard, area or beam)");
  }
  if (j.contains("shadow_samples"))
    r.shadow_samples = int(get_int(j["shadow_samples"], "settings.shadow_samples", 1, 4096));
  if (j.contains("transparent_shadows"))
    r.transparent_shadows = get_bool(j["transparent_shadows"], "settings.transparent_shadows");
  if (j.contains("width")) r.width = int(get_int(j["width"], "settings.width", 1, kMaxImageSide));
  if (j.contains("height")) r.height = int(get_int(j["height"], "settings.height", 1, kMaxImageSide));
  if (j.contains("spp")) r.spp = int(get_int(j["spp"], "settings.spp", 1, 1 << 20));
  if (j.contains("max_depth")) r.max_depth = int(get_int(j["max_depth"], "settings.max_depth", 0, 1000));
  if (j.contains("min_contribution"))
    r.min_contribution = get_float(j["min_contribution"], "settings.min_contribution", 0.0, 1.0, "in [0, 1]");
  if (j.contains("background")) r.background = get_color(j["background"], "settings.background");
  if (j.contains("seed")) {
    const json& v = j["seed"];
    if (!v.is_number_unsigned()) fail("settings.seed", "expected a non-negative integer");
    r.seed = v.get<uint64_t>();
  }
}

void parse_ambient(const json& j, Ambient& a) {
  require_object(j, "ambient");
  if (!j.contains("type")) fail("ambient.type", "missing (none, constant, hemisphere or irradiance_volume)");
  const std::string type = get_string(j["type"], "ambient.type");
  if (type == "none") {
    check_keys(j, "ambient", {"type"});
    a.kind = AmbientKind::kNone;
  } else if (type == "constant") {
    check_keys(j, "ambient", {"type", "color"});
    a.kind = AmbientKind::kConstant;
    if (j.contains("color")) a.constant = get_color(j["color"], "ambient.color");
  } else if (type == "hemisphere") {
    check_keys(j, "ambient", {"type", "a", "b", "axis"});
    a.kind = AmbientKind::kHemisphere;
    if (j.contains("a")) a.a = get_color(j["a"], "ambient.a");
    if (j.contains("b")) a.b = get_color(j["b"], "ambient.b");
    if (j.contains("axis")) a.axis = get_unit(j["axis"], "ambient.axis");
  } else if (type == "irradiance_volume") {
    check_keys(j, "ambient", {"type", "resolution", "samples"});
    a.kind = AmbientKind::kIrradianceVolume;
    if (j.contains("resolution")) a.volume_resolution = int(get_int(j["resolution"], "ambient.resolution", 1, 64));
    if (j.contains("samples")) a.volume_samples = int(get_int(j["samples"], "ambient.samples", 1, 65536));
  } else {
    fail("ambient.type", "unknown ambient '" + type + "' (none, constant, hemisphere or irradiance_volume)");
  }
}

void parse_lights(const json& j, Scene& s) {
  if (!j.is_array()) fail("lights", "expected an array, got " + type_name(j));
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string f = "lights[" + std::to_string(i) + "]";
    const json& l = require_object(j[i], f);
    const std::string type = l.contains("type") ? get_string(l["type"], f + ".type") : "point";
    Light light;
    if (type == "point") {
      check_keys(l, f, {"type", "position", "color"});
    } else if (type == "spherical") {
      check_keys(l, f, {"type", "position", "color", "radius"});
      if (!l.contains("radius")) fail(f + ".radius", "missing (a spherical light needs a radius > 0)");
      const double r = get_number(l["radius"], f + ".radius");
      if (!(r > 0.0)) fail(f + ".radius", "must be > 0 (got " + l["radius"].dump() + ")");
      light.radius = float(r);
    } else if (type == "directional") {
      // A sun: light travels along `direction`; angular_radius (degrees) > 0 softens shadows.
      check_keys(l, f, {"type", "direction", "color", "angular_radius"});
      light.kind = LightKind::kDirectional;
      light.direction = get_unit(need(l, f, "direction"), f + ".direction");
      if (l.contains("angular_radius"))
        light.angular_radius = glm::radians(
            get_float(l["angular_radius"], f + ".angular_radius", 0.0, 45.0, "in [0, 45] degrees"));
      if (l.contains("color")) light.color = get_color(l["color"], f + ".color");
      s.lights.push_back(light);
      continue;
    } else {
      fail(f + ".type", "unknown light '" + type + "' (point, spherical or directional)");
    }
    if (!l.contains("position")) fail(f + ".position", "missing");
    light.position = get_vec3(l["position"], f + ".position");
    if (l.contains("color")) light.color = get_color(l["color"], f + ".color");
    s.lights.push_back(light);
  }
}

struct Context {
  Scene& scene;
  std::map<std::string, uint16_t> materials;
  std::string base_dir;
  TextureNames textures;
  ImageCache images;
  std::set<uint32_t> object_space;  // solid textures that follow the object they are on
  PendingPhysics physics;           // physics balls, simulated once all objects are read
  std::map<std::string, uint32_t> shared;  // "meshes": name -> Geometry::instance_meshes index
};

// The object's material. A material with object-space solid textures is copied for the object,
// its textures re-framed by the inverse of object_to_world, so the pattern moves with the object.
uint16_t object_material(const json& o, const std::string& f, Context& ctx,
                         const glm::mat4& object_to_world = glm::mat4(1.0f)) {
  if (!o.contains("material")) fail(f + ".material", "missing");
  const std::string name = get_string(o["material"], f + ".material");
  const auto it = ctx.materials.find(name);
  if (it == ctx.materials.end()) fail(f + ".material", "unknown material '" + name + "'");
  Scene& s = ctx.scene;
  Material m = s.materials[it->second];
  bool moved = false;
  for (uint32_t* slot : {&m.kd_tex, &m.kh_tex, &m.ks_tex, &m.alpha_tex, &m.normal_tex, &m.bump_tex}) {
    if (*slot == kNoTexture || !ctx.object_space.count(*slot)) continue;
    Texture t = s.textures[*slot];
    t.to_texture = t.to_texture * glm::inverse(object_to_world);
    *slot = uint32_t(s.textures.size());
    s.textures.push_back(std::move(t));
    moved = true;
  }
  if (!moved) return it->second;
  if (s.materials.size() >= 65535) fail(f + ".material", "too many materials (at most 65535)");
  return add_material(s, m);
}

void check_mesh_size(const Scene& s, size_t more, const std::string& f) {
  if (s.geometry.positions.size() + more > size_t(0xfffffff0u)) fail(f, "scene has too many vertices");
}

void parse_triangles(const json& o, const std::string& f, Context& ctx, uint16_t mat,
                     const glm::mat4& m) {
  check_keys(o, f, {"type", "vertices", "normals", "uvs", "indices", "material", "transform"});
  MeshData mesh;
  const json& v = need(o, f, "vertices");
  if (!v.is_array()) fail(f + ".vertices", "expected an array of [x, y, z]");
  check_mesh_size(ctx.scene, v.size(), f + ".vertices");
  for (size_t i = 0; i < v.size(); ++i) mesh.positions.push_back(get_vec3(v[i], f + ".vertices[" + std::to_string(i) + "]"));
  if (o.contains("normals")) {
    const json& n = o["normals"];
    if (!n.is_array() || n.size() != v.size()) fail(f + ".normals", "expected one [x, y, z] per vertex");
    for (size_t i = 0; i < n.size(); ++i) mesh.normals.push_back(get_unit(n[i], f + ".normals[" + std::to_string(i) + "]"));
  }
  if (o.contains("uvs")) {
    const json& t = o["uvs"];
    if (!t.is_array() || t.size() != v.size()) fail(f + ".uvs", "expected one [u, v] per vertex");
    for (size_t i = 0; i < t.size(); ++i) {
      const std::string uf = f + ".uvs[" + std::to_string(i) + "]";
      if (!t[i].is_array() || t[i].size() != 2) fail(uf, "expected [u, v]");
      mesh.uvs.push_back(Vec2(float(get_number(t[i][0], uf + "[0]")), float(get_number(t[i][1], uf + "[1]"))));
    }
  }
  const json& ix = need(o, f, "indices");
  if (!ix.is_array()) fail(f + ".indices", "expected an array of [i, j, k]");
  for (size_t i = 0; i < ix.size(); ++i) {
    const std::string tf = f + ".indices[" + std::to_string(i) + "]";
    if (!ix[i].is_array() || ix[i].size() != 3) fail(tf, "expected 3 vertex indices");
    UVec3 t;
    for (int k = 0; k < 3; ++k) {
      const std::string kf = tf + "[" + std::to_string(k) + "]";
      if (mesh.positions.empty()) fail(kf, "index out of range (no vertices)");
      t[k] = uint32_t(get_int(ix[i][size_t(k)], kf, 0, int64_t(mesh.positions.size()) - 1));
    }
    mesh.triangles.push_back(t);
  }
  if (mesh.triangles.empty()) fail(f + ".indices", "empty mesh (no triangles)");
  add_mesh(ctx.scene, mesh, m, mat);
}

void parse_object(const json& o, const std::string& f, Context& ctx) {
  require_object(o, f);
  const std::string type = get_string(need(o, f, "type"), f + ".type");
  Scene& s = ctx.scene;
  if (type == "sphere") {
    check_keys(o, f, {"type", "center", "radius", "material", "motion", "dynamic", "name"});
    const Vec3 c = get_vec3(need(o, f, "center"), f + ".center");
    const double r = get_number(need(o, f, "radius"), f + ".radius");
    if (!(r > 0.0)) fail(f + ".radius", "must be > 0 (got " + o["radius"].dump() + ")");
    const bool dynamic = o.contains("motion") || (o.contains("dynamic") && get_bool(o["dynamic"], f + ".dynamic"));
    if (dynamic) {
      // Moving spheres stay out of the BVH (seed section 4); solid textures would not follow.
      const uint16_t mat = object_material(o, f, ctx);
      if (s.materials[mat].textured() || s.materials[mat].cutout())
        fail(f + ".material", "a moving sphere takes an untextured material");
      parse_dynamic_sphere(o, f, s, Sphere{c, float(r)}, mat, ctx.physics);
    } else {
      add_sphere(s, c, float(r), object_material(o, f, ctx, glm::translate(glm::mat4(1.0f), c)));
    }
  } else if (type == "mesh") {
    // OBJ (with its MTL materials when it names one), PLY, glTF or GLB; "material" overrides
    // the file's own materials and is required when the file has none.
    check_keys(o, f, {"type", "file", "transform", "material", "instancing"});
    const std::string file = get_string(need(o, f, "file"), f + ".file");
    const glm::mat4 m = o.contains("transform") ? parse_transform(o["transform"], f + ".transform") : glm::mat4(1.0f);
    const std::string full = !file.empty() && file[0] == '/' ? file : ctx.base_dir + "/" + file;
    auto mesh = load_model_mesh(full, ctx.images);
    if (!mesh) fail(f + ".file", mesh.error().message);
    check_mesh_size(s, mesh->positions.size(), f + ".file");
    const bool override_material = o.contains("material") || mesh->materials.empty();
    const uint16_t mat = override_material ? object_material(o, f, ctx, m) : 0;
    // glTF meshes that several nodes place become instances, except under "meshes" (an instance
    // holds no instances) or when the object asks for copies.
    const bool instancing = f.rfind("meshes.", 0) != 0 &&
                            (!o.contains("instancing") || get_bool(o["instancing"], f + ".instancing"));
    add_mesh(s, *mesh, m, mat, override_material, instancing);
  } else if (type == "triangles") {
    const glm::mat4 m = o.contains("transform") ? parse_transform(o["transform"], f + ".transform") : glm::mat4(1.0f);
    parse_triangles(o, f, ctx, object_material(o, f, ctx, m), m);
  } else if (type == "bezier") {
    const glm::mat4 m = o.contains("transform") ? parse_transform(o["transform"], f + ".transform") : glm::mat4(1.0f);
    parse_bezier(o, f, s, ctx.base_dir, object_material(o, f, ctx, m), m);
  } else if (type == "volume") {
    parse_volume(o, f, s, ctx.base_dir, [&](const json& name, const std::string& field) {
      const std::string n = get_string(name, field);
      const auto it = ctx.materials.find(n);
      if (it == ctx.materials.end()) fail(field, "unknown material '" + n + "'");
      return it->second;
    });
  } else if (type == "plane") {
    check_keys(o, f, {"type", "point", "normal", "size", "material"});
    const Vec3 p = get_vec3(need(o, f, "point"), f + ".point");
    const Vec3 n = get_unit(need(o, f, "normal"), f + ".normal");
    const double size = get_number(need(o, f, "size"), f + ".size");
    if (!(size > 0.0)) fail(f + ".size", "must be > 0 (got " + o["size"].dump() + ")");
    add_quad(s, p, n, float(size), object_material(o, f, ctx, glm::translate(glm::mat4(1.0f), p)));
  } else if (type == "box") {
    check_keys(o, f, {"type", "min", "max", "material"});
    const Vec3 lo = get_vec3(need(o, f, "min"), f + ".min");
    const Vec3 hi = get_vec3(need(o, f, "max"), f + ".max");
    if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z)) fail(f, "box min must be below max on every axis");
    add_box(s, lo, hi, object_material(o, f, ctx, glm::translate(glm::mat4(1.0f), 0.5f * (lo + hi))));
  } else if (type == "instance") {
    // One more placement of a mesh declared once under "meshes" (two-level BVH).
    check_keys(o, f, {"type", "mesh", "transform", "motion"});
    const std::string name = get_string(need(o, f, "mesh"), f + ".mesh");
    const auto it = ctx.shared.find(name);
    if (it == ctx.shared.end()) fail(f + ".mesh", "no mesh '" + name + "' under \"meshes\"");
    const glm::mat4 m = o.contains("transform") ? parse_transform(o["transform"], f + ".transform") : glm::mat4(1.0f);
    const Affine a = to_affine(m);
    Instance inst;
    if (!make_instance(it->second, a, inst)) fail(f + ".transform", "singular or non-finite transform");
    if (o.contains("motion"))  // moved by the application side, which publishes a refit top level
      parse_instance_motion(o["motion"], f + ".motion", s, uint32_t(s.geometry.instances.size()));
    s.geometry.instances.push_back(inst);
  } else if (type == "lightfield") {
    parse_lightfield(o, f, s, ctx.base_dir);
  } else {
    fail(f + ".type", "unknown object type '" + type + "' (sphere, mesh, triangles, bezier, plane, box, instance, volume or lightfield)");
  }
}

// "meshes": {"name": mesh or triangles object, ...}: each is loaded and built once, in its own
// object space, and placed by "instance" objects.
void parse_shared_meshes(const json& j, Context& ctx) {
  const json& meshes = require_object(j, "meshes");
  for (auto it = meshes.begin(); it != meshes.end(); ++it) {
    const std::string f = "meshes." + it.key();
    require_object(it.value(), f);
    const std::string type = get_string(need(it.value(), f, "type"), f + ".type");
    if (type != "mesh" && type != "triangles") fail(f + ".type", "a shared mesh is of type mesh or triangles");
    // Parsed like an object into an empty geometry, which then becomes the shared mesh.
    Geometry scene_geometry;
    std::swap(scene_geometry, ctx.scene.geometry);
    auto mesh = std::make_shared<InstancedMesh>();
    try {
      parse_object(it.value(), f, ctx);
    } catch (...) {
      std::swap(scene_geometry, ctx.scene.geometry);
      throw;
    }
    mesh->geometry = std::move(ctx.scene.geometry);
    ctx.scene.geometry = std::move(scene_geometry);
    mesh->name = it.key();
    build_instanced_mesh(*mesh);
    ctx.shared[it.key()] = uint32_t(ctx.scene.geometry.instance_meshes.size());
    ctx.scene.geometry.instance_meshes.push_back(std::move(mesh));
  }
}

void parse_scene(const json& root, Context& ctx) {
  Scene& s = ctx.scene;
  require_object(root, "(top level)");
  check_keys(root, "", {"camera", "settings", "ambient", "lights", "textures", "materials", "objects",
                        "physics", "meshes"});
  if (root.contains("settings")) {
    parse_settings(root["settings"], s.settings);
    if (root["settings"].contains("environment"))
      parse_environment(root["settings"]["environment"], s, ctx.base_dir, ctx.images);
  }
  s.ambient = default_hemisphere_ambient();
  if (root.contains("ambient")) parse_ambient(root["ambient"], s.ambient);
  if (root.contains("lights")) parse_lights(root["lights"], s);
  if (root.contains("textures"))
    parse_textures(root["textures"], s, ctx.base_dir, ctx.images, ctx.textures, ctx.object_space);
  if (root.contains("materials")) {
    const json& mats = require_object(root["materials"], "materials");
    if (mats.size() > 65535) fail("materials", "too many materials (at most 65535)");
    for (auto it = mats.begin(); it != mats.end(); ++it) {
      const std::string f = "materials." + it.key();
      const bool shaded = it.value().is_object() && it.value().contains("shader");
      ctx.materials[it.key()] = add_material(s, shaded ? parse_shader_material(it.key(), it.value(), f, s, ctx.base_dir, ctx.textures)
                                                       : parse_material(it.key(), it.value(), f, ctx.textures, s));
    }
  }
  if (root.contains("meshes")) parse_shared_meshes(root["meshes"], ctx);
  if (!root.contains("objects")) fail("objects", "missing (a scene needs at least one object)");
  const json& objs = root["objects"];
  if (!objs.is_array()) fail("objects", "expected an array, got " + type_name(objs));
  if (objs.empty()) fail("objects", "empty (a scene needs at least one object)");
  for (size_t i = 0; i < objs.size(); ++i) parse_object(objs[i], "objects[" + std::to_string(i) + "]", ctx);
  finish_physics(root.contains("physics") ? &root["physics"] : nullptr, s, ctx.physics);
  Vec3 lo, hi;
  geometry_bounds(s.geometry, lo, hi);
  for (const Instance& inst : s.geometry.instances) {  // and on instances
    Vec3 ilo, ihi;
    instance_bounds(inst, *s.geometry.instance_meshes[inst.mesh], ilo, ihi);
    lo = glm::min(lo, ilo);
    hi = glm::max(hi, ihi);
  }
  for (const DynamicObject& d : s.dynamic) {  // frame the camera on moving objects too
    lo = glm::min(lo, d.sphere.center - Vec3(d.sphere.radius));
    hi = glm::max(hi, d.sphere.center + Vec3(d.sphere.radius));
  }
  for (const VolumeObject& v : s.volumes) lo = glm::min(lo, v.lo), hi = glm::max(hi, v.hi);  // and on volumes
  for (const LightfieldObject& l : s.lightfields) lo = glm::min(lo, l.lo), hi = glm::max(hi, l.hi);  // lightfields
  if (!is_finite(lo) || !is_finite(hi)) fail("objects", "geometry extends beyond finite coordinates");
  if (root.contains("camera")) {
    parse_camera(root["camera"], s);
  } else {
    s.camera = frame_camera(lo, hi, s.settings.width, s.settings.height);
  }
}

// Line and column (1-based) of a byte offset.
std::string line_col(const std::string& text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < std::min(byte, text.size()); ++i) {
    if (text[i] == '\n') ++line, col = 1;
    else ++col;
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

}  // namespace

Result<std::unique_ptr<Scene>> parse_scene_json(const std::string& text, const std::string& path,
                                                const std::string& base_dir) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's message carries "[json.exception...] parse error at line L, column C: WHAT".
    std::string what = e.what();
    const size_t colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    for (char& c : what)
      if (c == '\n' || c == '\r') c = ' ';
    // e.byte is one past the offending character.
    return Error{path + ":" + line_col(text, e.byte > 0 ? e.byte - 1 : 0) + ": JSON syntax error: " + what};
  } catch (const json::exception& e) {
    // A number too large for a double ("1e999") is reported without a position: find the
    // token nlohmann quotes in its message to name the line.
    std::string what = e.what();
    const size_t colon = what.find("] ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    const size_t q1 = what.find('\''), q2 = what.rfind('\'');
    std::string where;
    if (q1 != std::string::npos && q2 > q1 + 1) {
      const size_t at = text.find(what.substr(q1 + 1, q2 - q1 - 1));
      if (at != std::string::npos) where = ":" + line_col(text, at);
    }
    return Error{path + where + ": JSON error: " + what};
  }
  auto scene = std::make_unique<Scene>();
  const size_t slash = path.find_last_of('/');
  scene->name = slash == std::string::npos ? path : path.substr(slash + 1);
  Context ctx{*scene, {}, base_dir, {}, {}, {}, {}};
  try {
    parse_scene(root, ctx);
  } catch (const Failure& f) {
    // Keys and values are quoted as written, and JSON strings may hold line breaks.
    return Error{one_line(path + ": " + f.field + ": " + f.what)};
  } catch (const json::exception& e) {
    return Error{one_line(path + ": " + e.what())};
  }
  finalize_scene(*scene);
  return scene;
}

Result<std::unique_ptr<Scene>> load_scene_json(const std::string& path) {
  auto bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  const size_t slash = path.find_last_of('/');
  const std::string base_dir = slash == std::string::npos ? "." : path.substr(0, slash);
  return parse_scene_json(*bytes, path, base_dir.empty() ? "/" : base_dir);
}

}  // namespace frameless
