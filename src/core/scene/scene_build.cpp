#include "core/scene/scene_build.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_inverse.hpp>

#include "core/accel/instance.h"

namespace frameless {

uint16_t add_material(Scene& scene, const Material& m) {
  scene.materials.push_back(m);
  return uint16_t(scene.materials.size() - 1);
}

// Gives triangles [first, end) their own vertices carrying the face normal, so that flat
// geometry keeps flat shading in a scene where other meshes bring vertex normals. UVs, when the
// scene has them, follow their vertices.
static void append_flat_normals(Geometry& g, size_t first) {
  std::vector<Vec3> pos = std::move(g.positions);
  std::vector<Vec2> uv = std::move(g.uvs);
  const auto kept = std::ptrdiff_t(g.normals.size());
  g.positions.assign(pos.begin(), pos.begin() + kept);
  if (!uv.empty()) g.uvs.assign(uv.begin(), uv.begin() + kept);
  for (size_t i = first; i < g.triangles.size(); ++i) {
    const UVec3 t = g.triangles[i];
    Vec3 n = glm::cross(pos[t.y] - pos[t.x], pos[t.z] - pos[t.x]);
    const float len = glm::length(n);
    n = len > 0.0f && std::isfinite(len) ? n / len : Vec3(0.0f, 1.0f, 0.0f);
    const uint32_t b = uint32_t(g.positions.size());
    for (int k = 0; k < 3; ++k) {
      g.positions.push_back(pos[t[k]]);
      g.normals.push_back(n);
      if (!uv.empty()) g.uvs.push_back(uv[t[k]]);
    }
    g.triangles[i] = UVec3(b, b + 1, b + 2);
  }
}

namespace {

// Scene material of a mesh's faces: the caller's for every face, or the mesh's own moved past
// `base` (add_own_materials).
struct FaceMaterials {
  bool own = false;
  uint16_t fixed = 0;
  size_t base = 0, count = 0;
  uint16_t of(const MeshData& part, size_t i) const {
    if (!own) return fixed;
    size_t fm = part.face_material.size() == part.triangles.size() ? part.face_material[i] : 0;
    if (fm >= count) fm = 0;
    // Ids are 16-bit; past 65535 materials the last id still names a valid one.
    return uint16_t(std::min<size_t>(base + fm, 0xffff));
  }
};

// A mesh that carries materials brings them and its textures into the scene once, for its flat
// part and its shared meshes alike.
FaceMaterials add_own_materials(Scene& scene, const MeshData& mesh, uint16_t material,
                                bool override_material) {
  FaceMaterials fm;
  fm.fixed = material;
  fm.own = !mesh.materials.empty() && !override_material;
  if (!fm.own) return fm;
  // Texture slots moved past the scene's textures.
  const uint32_t tex_base = uint32_t(scene.textures.size());
  scene.textures.insert(scene.textures.end(), mesh.textures.begin(), mesh.textures.end());
  fm.base = scene.materials.size();
  fm.count = mesh.materials.size();
  for (Material mm : mesh.materials) {
    for (uint32_t* slot :
         {&mm.kd_tex, &mm.kh_tex, &mm.ks_tex, &mm.alpha_tex, &mm.normal_tex, &mm.bump_tex})
      if (*slot != kNoTexture) *slot += tex_base;
    scene.materials.push_back(std::move(mm));
  }
  return fm;
}

// Appends one mesh part (the flat mesh or a shared one) to g under m.
void append_part(Geometry& g, const MeshData& mesh, const glm::mat4& m, const FaceMaterials& fm) {
  const glm::mat3 nm = glm::inverseTranspose(glm::mat3(m));
  const bool mirrored = glm::determinant(glm::mat3(m)) < 0.0f;
  const bool has_normals = !mesh.normals.empty() && mesh.normals.size() == mesh.positions.size();
  const bool has_uvs = !mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size();
  // Vertex normals and uvs are all-or-nothing per scene (one per position, or none): earlier
  // geometry gets flat normals and zero uvs when the first mesh that has them arrives.
  if (has_uvs && g.uvs.empty()) g.uvs.assign(g.positions.size(), Vec2(0.0f));
  if (has_normals && g.normals.empty() && !g.triangles.empty()) append_flat_normals(g, 0);
  const bool scene_normals = !g.normals.empty() || has_normals;
  const uint32_t base = uint32_t(g.positions.size());
  const size_t first_tri = g.triangles.size();
  g.positions.reserve(g.positions.size() + mesh.positions.size());
  for (const Vec3& p : mesh.positions) g.positions.push_back(Vec3(m * Vec4(p, 1.0f)));
  if (has_uvs) g.uvs.insert(g.uvs.end(), mesh.uvs.begin(), mesh.uvs.end());
  else if (!g.uvs.empty()) g.uvs.resize(g.positions.size(), Vec2(0.0f));
  g.triangles.reserve(g.triangles.size() + mesh.triangles.size());
  g.triangle_material.reserve(g.triangles.size() + mesh.triangles.size());
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const UVec3 s = mesh.triangles[i] + UVec3(base);
    g.triangles.push_back(mirrored ? UVec3(s.x, s.z, s.y) : s);
    g.triangle_material.push_back(fm.of(mesh, i));
  }
  if (has_normals) {
    g.normals.reserve(g.positions.size());
    for (const Vec3& n : mesh.normals) {
      const Vec3 t = nm * n;
      const float len = glm::length(t);
      g.normals.push_back(len > 0.0f && std::isfinite(len) ? t / len : Vec3(0.0f, 1.0f, 0.0f));
    }
  } else if (scene_normals) {
    append_flat_normals(g, first_tri);
  }
}

Affine to_affine(const glm::mat4& m) {
  Affine a;
  a.m = glm::mat3(m);
  a.t = Vec3(m[3]);
  return a;
}

// The shared meshes' placements: one InstancedMesh per shared mesh (built on its first
// placement, materials as the scene's ids) and one Instance per placement; a placement whose
// transform cannot be inverted becomes a copy, as flattening would give.
void place_shared(Scene& scene, const MeshData& mesh, const glm::mat4& m, const FaceMaterials& fm) {
  Geometry& g = scene.geometry;
  std::vector<uint32_t> built(mesh.shared.size(), kInvalidId);
  for (const MeshPlacement& p : mesh.placements) {
    if (p.mesh >= mesh.shared.size() || mesh.shared[p.mesh].triangles.empty()) continue;
    const MeshData& part = mesh.shared[p.mesh];
    const glm::mat4 w = m * p.to_model;
    Instance inst;
    if (!make_instance(0, to_affine(w), inst)) {
      append_part(g, part, w, fm);
      continue;
    }
    if (built[p.mesh] == kInvalidId) {
      auto shared = std::make_shared<InstancedMesh>();
      shared->name = scene.name + " mesh " + std::to_string(p.mesh);
      append_part(shared->geometry, part, glm::mat4(1.0f), fm);  // alone, in object space
      build_instanced_mesh(*shared);
      built[p.mesh] = uint32_t(g.instance_meshes.size());
      g.instance_meshes.push_back(std::move(shared));
    }
    inst.mesh = built[p.mesh];
    g.instances.push_back(inst);
  }
}

}  // namespace

void add_mesh(Scene& scene, const MeshData& mesh, const glm::mat4& m, uint16_t material,
              bool override_material, bool instancing) {
  const FaceMaterials fm = add_own_materials(scene, mesh, material, override_material);
  append_part(scene.geometry, mesh, m, fm);
  if (instancing) {
    place_shared(scene, mesh, m, fm);
    return;
  }
  for (const MeshPlacement& p : mesh.placements)
    if (p.mesh < mesh.shared.size())
      append_part(scene.geometry, mesh.shared[p.mesh], m * p.to_model, fm);
}

void add_quad(Scene& scene, const Vec3& center, const Vec3& normal, float size, uint16_t material) {
  const Vec3 n = glm::normalize(normal);
  const Vec3 helper = std::fabs(n.y) < 0.9f ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 a = glm::normalize(glm::cross(helper, n)) * (0.5f * size);
  const Vec3 b = glm::cross(n, glm::normalize(a)) * (0.5f * size);
  MeshData q;
  // a x b is along n, so counter-clockwise (a, b) order faces along n; u runs along a, v along b.
  q.positions = {center - a - b, center + a - b, center + a + b, center - a + b};
  q.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  q.triangles = {UVec3(0, 1, 2), UVec3(0, 2, 3)};
  add_mesh(scene, q, glm::mat4(1.0f), material);
}

void add_box(Scene& scene, const Vec3& lo, const Vec3& hi, uint16_t material) {
  MeshData b;
  auto corner = [&](int i) {
    return Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  };
  // Each face's corners counter-clockwise seen from outside, starting bottom-left as seen from
  // outside (sides upright, the top with v towards -z), so uv 0..1 spans every face.
  const int faces[6][4] = {{0, 4, 6, 2},   // -x
                           {5, 1, 3, 7},   // +x
                           {0, 1, 5, 4},   // -y
                           {6, 7, 3, 2},   // +y
                           {1, 0, 2, 3},   // -z
                           {4, 5, 7, 6}};  // +z
  for (const auto& f : faces) {
    const uint32_t v = uint32_t(b.positions.size());
    for (int k = 0; k < 4; ++k) b.positions.push_back(corner(f[k]));
    b.uvs.insert(b.uvs.end(), {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)});
    b.triangles.push_back(UVec3(v, v + 1, v + 2));
    b.triangles.push_back(UVec3(v, v + 2, v + 3));
  }
  add_mesh(scene, b, glm::mat4(1.0f), material);
}

void add_sphere(Scene& scene, const Vec3& center, float radius, uint16_t material) {
  scene.geometry.spheres.push_back(Sphere{center, radius});
  scene.geometry.sphere_material.push_back(material);
}

Camera frame_camera(const Vec3& lo, const Vec3& hi, int width, int height) {
  Camera cam;
  cam.fov_deg = 40.0f;
  const Vec3 c = 0.5f * (lo + hi);
  const float r = std::max(0.5f * glm::length(hi - lo), 1e-6f);
  // Fit the bounding sphere in the narrower of the two fields of view.
  float half = glm::radians(cam.fov_deg) * 0.5f;
  if (width < height) half = std::atan(std::tan(half) * float(width) / float(height));
  const float dist = 1.05f * r / std::sin(half);
  cam.eye = c + dist * glm::normalize(Vec3(0.35f, 0.3f, 1.0f));
  cam.look = c;
  cam.up = Vec3(0.0f, 1.0f, 0.0f);
  return cam;
}

Ambient default_hemisphere_ambient() {
  Ambient a;
  a.kind = AmbientKind::kHemisphere;
  a.a = Vec3(0.22f, 0.26f, 0.32f);
  a.b = Vec3(0.06f, 0.05f, 0.04f);
  a.axis = Vec3(0.0f, 1.0f, 0.0f);
  return a;
}

namespace {

// Placed vertices whose bounds are taken one by one (the vertices flattening would have
// transformed); past them a placement's bounds are its transformed object box.
constexpr size_t kExactBoundVertices = size_t(1) << 27;

void grow(Vec3& lo, Vec3& hi, const Vec3& p) {
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

// Grows [lo, hi] by the vertices of part's triangles under m.
void grow_by_part(const MeshData& part, const glm::mat4& m, Vec3& lo, Vec3& hi) {
  for (const UVec3& t : part.triangles)
    for (int k = 0; k < 3; ++k) grow(lo, hi, Vec3(m * Vec4(part.positions[t[k]], 1.0f)));
}

}  // namespace

void mesh_bounds(const MeshData& mesh, const glm::mat4& m, Vec3& lo, Vec3& hi) {
  lo = Vec3(kInfinity);
  hi = Vec3(-kInfinity);
  grow_by_part(mesh, m, lo, hi);
  size_t budget = kExactBoundVertices;
  std::vector<std::pair<Vec3, Vec3>> boxes;  // object boxes of the shared meshes, on demand
  for (const MeshPlacement& p : mesh.placements) {
    if (p.mesh >= mesh.shared.size()) continue;
    const MeshData& part = mesh.shared[p.mesh];
    const glm::mat4 w = m * p.to_model;
    if (3 * part.triangles.size() <= budget) {
      budget -= 3 * part.triangles.size();
      grow_by_part(part, w, lo, hi);
      continue;
    }
    if (boxes.empty()) {
      boxes.assign(mesh.shared.size(), {Vec3(kInfinity), Vec3(-kInfinity)});
      for (size_t i = 0; i < mesh.shared.size(); ++i)
        grow_by_part(mesh.shared[i], glm::mat4(1.0f), boxes[i].first, boxes[i].second);
    }
    const auto& [blo, bhi] = boxes[p.mesh];
    if (!(blo.x <= bhi.x)) continue;  // no triangles
    for (int k = 0; k < 8; ++k) {
      const Vec3 c(k & 1 ? bhi.x : blo.x, k & 2 ? bhi.y : blo.y, k & 4 ? bhi.z : blo.z);
      grow(lo, hi, Vec3(w * Vec4(c, 1.0f)));
    }
  }
}

std::unique_ptr<Scene> make_mesh_scene(MeshData mesh, const std::string& name) {
  auto scene = std::make_unique<Scene>();
  scene->name = name;
  if (mesh.materials.empty()) {
    Material m;
    m.name = "default";
    m.cls = MaterialClass::kDiffuse;
    m.kd = Vec3(0.75f, 0.72f, 0.68f);
    add_mesh(*scene, mesh, glm::mat4(1.0f), add_material(*scene, m), false, true);
  } else {
    add_mesh(*scene, mesh, glm::mat4(1.0f), 0, false, true);  // the file's own materials
  }
  Vec3 lo, hi;
  mesh_bounds(mesh, glm::mat4(1.0f), lo, hi);
  const Vec3 c = 0.5f * (lo + hi);
  const float r = std::max(0.5f * glm::length(hi - lo), 1e-6f);
  scene->lights.push_back(Light{c + r * Vec3(2.0f, 4.0f, 3.0f), Vec3(0.85f), 0.0f});
  scene->ambient = default_hemisphere_ambient();
  scene->camera = frame_camera(lo, hi, scene->settings.width, scene->settings.height);
  return scene;
}

}  // namespace frameless
