// The "sunflowers" built-in scene after OpenRT's sunflower field (Wald et al. 2003, figure 2):
// ten procedurally generated plant kinds (eight sunflowers, two trees; tens of thousands of
// triangles each, leaves with cut-out textures) placed tens of thousands of times by instances,
// about one billion triangles represented, lit by a low sun whose shadows fall through the leaves.
#include <charconv>
#include <cmath>
#include <string_view>

#include "core/accel/instance.h"
#include "core/base/rng.h"
#include "core/scene/scene_build.h"
#include "core/scene/scene_finalize.h"
#include "core/scenes/builtin_scenes.h"

namespace frameless {
namespace {

// Appends vertices and triangles to one mesh.
struct MeshBuilder {
  Geometry& g;
  uint32_t vertex(const Vec3& p, const Vec3& n, const Vec2& uv) {
    g.positions.push_back(p);
    g.normals.push_back(n);
    g.uvs.push_back(uv);
    return uint32_t(g.positions.size() - 1);
  }
  void tri(uint32_t a, uint32_t b, uint32_t c, uint16_t m) {
    g.triangles.push_back({a, b, c});
    g.triangle_material.push_back(m);
  }
  // A grid of (nu + 1) x (nv + 1) vertices from f(u, v) -> (position, normal), u, v in [0, 1].
  template <class F>
  void grid(int nu, int nv, uint16_t m, F&& f) {
    const uint32_t base = uint32_t(g.positions.size());
    for (int j = 0; j <= nv; ++j)
      for (int i = 0; i <= nu; ++i) {
        const float u = float(i) / float(nu), v = float(j) / float(nv);
        Vec3 p, n;
        f(u, v, p, n);
        vertex(p, n, Vec2(u, v));
      }
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const uint32_t a = base + uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1),
                       d = c + 1;
        tri(a, b, d, m);
        tri(a, d, c, m);
      }
  }
};

struct Materials {
  uint16_t stem, leaf, petal, florets, back, bark, foliage;
};

// A tube of radius r(v) along a curve c(v), v in [0, 1].
template <class C, class R>
void tube(MeshBuilder& mb, int sides, int rings, uint16_t m, C&& curve, R&& radius) {
  mb.grid(sides, rings, m, [&](float u, float v, Vec3& p, Vec3& n) {
    const float a = 2.0f * kPi * u;
    const Vec3 c = curve(v);
    n = Vec3(std::cos(a), 0.0f, std::sin(a));
    p = c + radius(v) * n;
  });
}

// A leaf blade: a curved grid whose texture's alpha cuts out the leaf's outline.
void leaf(MeshBuilder& mb, const Vec3& base, float yaw, float length, float width, float droop,
          uint16_t m) {
  const Vec3 out(std::cos(yaw), 0.0f, std::sin(yaw)), side(-out.z, 0.0f, out.x);
  mb.grid(6, 10, m, [&](float u, float v, Vec3& p, Vec3& n) {
    const float along = v * length, across = (u - 0.5f) * width;
    // Rises, then droops; the sides curl up a little.
    const float h = along * (0.45f - droop * v) + 0.15f * width * (2.0f * u - 1.0f) * (2.0f * u - 1.0f);
    p = base + along * out + across * side + Vec3(0.0f, h, 0.0f);
    const Vec3 dv = out + Vec3(0.0f, 0.45f - 2.0f * droop * v, 0.0f);
    n = glm::normalize(glm::cross(dv, side));
  });
}

// A sunflower: a bent stem, leaves, a head of florets in Vogel's phyllotaxis spiral, petals.
void sunflower(Geometry& g, const Materials& mat, uint64_t seed, float height, float head_r,
               int florets, int leaves) {
  MeshBuilder mb{g};
  Rng rng(seed);
  const float bend = 0.08f + 0.1f * rng.next_float();
  auto stem_at = [&](float v) { return Vec3(0.0f, height * v, bend * v * v * height); };
  tube(mb, 10, 24, mat.stem, stem_at, [&](float v) { return 0.035f * (1.0f - 0.4f * v); });
  for (int k = 0; k < leaves; ++k) {
    const float v = 0.15f + 0.7f * float(k) / float(leaves);
    const float size = 0.42f * (1.1f - 0.6f * v);
    leaf(mb, stem_at(v), 2.39996f * float(k) + rng.next_float(), size, 0.7f * size,
         0.35f + 0.2f * rng.next_float(), mat.leaf);
  }
  // The head faces +z, tilted down a little.
  const Vec3 centre = stem_at(1.0f) + Vec3(0.0f, 0.02f, 0.06f);
  const Vec3 f = glm::normalize(Vec3(0.0f, -0.25f, 1.0f)), r(1.0f, 0.0f, 0.0f);
  const Vec3 up = glm::cross(f, r);
  // Florets: small four-sided pyramids on a slightly domed disc (golden-angle spiral).
  const float cell = head_r * 1.7f / std::sqrt(float(florets));
  for (int i = 0; i < florets; ++i) {
    const float rad = head_r * std::sqrt((float(i) + 0.5f) / float(florets));
    const float a = 2.39996323f * float(i);
    const Vec3 c = centre + rad * (std::cos(a) * r + std::sin(a) * up) +
                   (0.05f * head_r * (1.0f - rad * rad / (head_r * head_r))) * f;
    const Vec3 tip = c + 0.6f * cell * f;
    uint32_t ring[4];
    for (int k = 0; k < 4; ++k) {
      const float b = a + 0.5f * kPi * float(k);
      ring[k] = mb.vertex(c + 0.5f * cell * (std::cos(b) * r + std::sin(b) * up), f, Vec2(0.5f));
    }
    const uint32_t t = mb.vertex(tip, f, Vec2(0.5f));
    for (int k = 0; k < 4; ++k) mb.tri(ring[k], ring[(k + 1) % 4], t, mat.florets);
  }
  // The back of the head: a shallow cone.
  mb.grid(24, 3, mat.back, [&](float u, float v, Vec3& p, Vec3& n) {
    const float a = 2.0f * kPi * u, rad = head_r * 1.05f * (1.0f - v);
    const Vec3 radial = std::cos(a) * r + std::sin(a) * up;
    p = centre + rad * radial - (0.12f * head_r * v) * f;
    n = glm::normalize(radial - 0.5f * f);
  });
  // Petals: thin curved blades around the rim.
  const int petals = 34;
  for (int k = 0; k < petals; ++k) {
    const float a = 2.0f * kPi * (float(k) + 0.5f * float(k & 1)) / float(petals);
    const Vec3 radial = std::cos(a) * r + std::sin(a) * up, tangent = glm::cross(f, radial);
    const float len = head_r * (0.8f + 0.2f * rng.next_float());
    mb.grid(2, 5, mat.petal, [&](float u, float v, Vec3& p, Vec3& n) {
      const float w = 0.11f * len * std::sin(kPi * std::min(1.0f, v * 1.2f + 0.1f)) * (2.0f * u - 1.0f);
      p = centre + (head_r + v * len) * radial + w * tangent - (0.15f * len * v * v) * f;
      n = f;
    });
  }
}

// A tree: trunk, branches, and many cut-out leaf cards in a crown.
void tree(Geometry& g, const Materials& mat, uint64_t seed, float height, int cards) {
  MeshBuilder mb{g};
  Rng rng(seed);
  tube(mb, 14, 20, mat.bark, [&](float v) { return Vec3(0.0f, height * 0.6f * v, 0.0f); },
       [&](float v) { return 0.28f * (1.0f - 0.5f * v); });
  const Vec3 crown(0.0f, height * 0.68f, 0.0f);
  const float radius = height * 0.33f;
  for (int b = 0; b < 9; ++b) {
    const float a = 2.0f * kPi * rng.next_float(), up = 0.3f + 0.5f * rng.next_float();
    const Vec3 from(0.0f, height * (0.4f + 0.2f * rng.next_float()), 0.0f);
    const Vec3 to = crown + radius * 0.9f * Vec3(std::cos(a), up, std::sin(a));
    tube(mb, 6, 6, mat.bark, [&](float v) { return from + v * (to - from); },
         [&](float v) { return 0.09f * (1.0f - 0.7f * v); });
  }
  for (int k = 0; k < cards; ++k) {
    Vec3 d;
    do d = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 2.0f - Vec3(1.0f);
    while (glm::dot(d, d) > 1.0f);
    const Vec3 c = crown + radius * Vec3(d.x, 0.75f * d.y, d.z);
    const float yaw = 2.0f * kPi * rng.next_float(), s = 0.35f + 0.2f * rng.next_float();
    const Vec3 a(std::cos(yaw), 0.3f * (rng.next_float() - 0.5f), std::sin(yaw));
    const Vec3 n = glm::normalize(glm::cross(a, Vec3(0.0f, 1.0f, 0.0f)) + Vec3(0.0f, 0.6f, 0.0f));
    const Vec3 b = glm::normalize(glm::cross(n, a));
    const uint32_t v0 = mb.vertex(c - s * a - s * b, n, Vec2(0, 0));
    const uint32_t v1 = mb.vertex(c + s * a - s * b, n, Vec2(1, 0));
    const uint32_t v2 = mb.vertex(c + s * a + s * b, n, Vec2(1, 1));
    const uint32_t v3 = mb.vertex(c - s * a + s * b, n, Vec2(0, 1));
    mb.tri(v0, v1, v2, mat.foliage);
    mb.tri(v0, v2, v3, mat.foliage);
  }
}

// A 64x64 leaf: green with a darker midrib, alpha 0 outside a pointed oval (the cut-out).
std::shared_ptr<Image> leaf_image() {
  auto img = std::make_shared<Image>();
  img->path = "sunflowers:leaf";
  img->width = img->height = 64;
  img->channels = 4;
  img->ldr.resize(64 * 64 * 4);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float u = (float(x) + 0.5f) / 64.0f, v = 1.0f - (float(y) + 0.5f) / 64.0f;
      // Half-width of the blade at v: wide near the base, pointed at the tip, a serrated edge.
      const float half = 0.5f * std::sin(kPi * std::pow(v, 0.8f)) * (0.92f + 0.08f * std::sin(60.0f * v));
      const bool inside = std::fabs(u - 0.5f) < half && v > 0.02f;
      const float vein = std::fabs(u - 0.5f) < 0.03f ? 0.7f : 1.0f;
      uint8_t* t = &img->ldr[size_t(y * 64 + x) * 4];
      t[0] = uint8_t(70 * vein), t[1] = uint8_t((130 + 40 * v) * vein), t[2] = uint8_t(40 * vein);
      t[3] = inside ? 255 : 0;
    }
  return img;
}

Material textured_leaf(Scene& s, const char* name, const Vec3& tint) {
  Material m = diffuse(name, tint);
  Texture t;
  t.kind = TextureKind::kImage;
  t.image = leaf_image();
  s.textures.push_back(t);
  m.kd_tex = m.alpha_tex = uint32_t(s.textures.size() - 1);
  m.alpha_channel = 3;
  return m;
}

}  // namespace

namespace {

// Copies every instance's mesh, transformed, into the scene's own arrays: one plain mesh.
void flatten_instances(Geometry& g) {
  size_t verts = g.positions.size(), tris = g.triangles.size();
  for (const Instance& inst : g.instances) {
    verts += g.instance_meshes[inst.mesh]->geometry.positions.size();
    tris += g.instance_meshes[inst.mesh]->geometry.triangles.size();
  }
  // Flat vertex arrays need every vertex to carry a normal and uv, as the meshes' do.
  g.normals.resize(g.positions.size(), Vec3(0.0f, 1.0f, 0.0f));
  g.uvs.resize(g.positions.size(), Vec2(0.0f));
  g.positions.reserve(verts), g.normals.reserve(verts), g.uvs.reserve(verts);
  g.triangles.reserve(tris), g.triangle_material.reserve(tris);
  for (const Instance& inst : g.instances) {
    const Geometry& m = g.instance_meshes[inst.mesh]->geometry;
    const uint32_t base = uint32_t(g.positions.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
      g.positions.push_back(inst.to_world.point(m.positions[i]));
      g.normals.push_back(glm::normalize(inst.normal_to_world * m.normals[i]));
      g.uvs.push_back(m.uvs[i]);
    }
    for (const UVec3& t : m.triangles) g.triangles.push_back(t + base);
    g.triangle_material.insert(g.triangle_material.end(), m.triangle_material.begin(),
                               m.triangle_material.end());
  }
  g.instances.clear();
  g.instance_meshes.clear();
}

}  // namespace

Result<std::unique_ptr<Scene>> make_sunflowers(uint64_t plants, bool flat) {
  auto s = std::make_unique<Scene>();
  s->name = "sunflowers";
  Materials mat;
  mat.stem = add_material(*s, diffuse("stem", Vec3(0.25f, 0.42f, 0.12f)));
  mat.leaf = add_material(*s, textured_leaf(*s, "leaf", Vec3(1.0f)));
  mat.petal = add_material(*s, diffuse("petal", Vec3(0.95f, 0.72f, 0.08f)));
  mat.florets = add_material(*s, polished("florets", Vec3(0.22f, 0.12f, 0.04f), 0.03f));
  mat.back = add_material(*s, diffuse("head", Vec3(0.3f, 0.45f, 0.15f)));
  mat.bark = add_material(*s, diffuse("bark", Vec3(0.32f, 0.24f, 0.17f)));
  mat.foliage = add_material(*s, textured_leaf(*s, "foliage", Vec3(0.8f, 0.9f, 0.7f)));
  const uint16_t soil = add_material(*s, diffuse("soil", Vec3(0.36f, 0.27f, 0.18f)));

  // Eight sunflower kinds and two trees, each built once.
  Geometry& g = s->geometry;
  for (int k = 0; k < 10; ++k) {
    auto mesh = std::make_shared<InstancedMesh>();
    if (k < 8) {
      mesh->name = "sunflower" + std::to_string(k);
      sunflower(mesh->geometry, mat, 101 + uint64_t(k), 1.5f + 0.12f * float(k), 0.16f + 0.012f * float(k),
                2600 + 600 * k, 8 + k % 4);
    } else {
      mesh->name = "tree" + std::to_string(k - 8);
      tree(mesh->geometry, mat, 201 + uint64_t(k), 9.0f + 3.0f * float(k - 8), 12000);
    }
    build_instanced_mesh(*mesh);
    g.instance_meshes.push_back(std::move(mesh));
  }
  // The field: rows of sunflowers facing the sun (+z, small random turns), a few trees behind.
  const int side = std::max(1, int(std::ceil(std::sqrt(double(plants)))));
  const float spacing = 0.75f;
  Rng rng(7);
  for (uint64_t i = 0; i < plants; ++i) {
    const int row = int(i / uint64_t(side)), col = int(i % uint64_t(side));
    const float x = (float(col) - 0.5f * float(side)) * spacing + 0.25f * (rng.next_float() - 0.5f);
    const float z = -float(row) * spacing + 0.25f * (rng.next_float() - 0.5f);
    const float turn = 0.5f * (rng.next_float() - 0.5f), scale = 0.85f + 0.3f * rng.next_float();
    const float stretch_y = 0.9f + 0.25f * rng.next_float();  // non-uniform: taller or shorter
    Affine a;
    const float c = std::cos(turn), sn = std::sin(turn);
    a.m = glm::mat3(Vec3(c * scale, 0.0f, -sn * scale), Vec3(0.0f, scale * stretch_y, 0.0f),
                    Vec3(sn * scale, 0.0f, c * scale));
    a.t = Vec3(x, 0.0f, z);
    Instance inst;
    if (make_instance(uint32_t(rng.next_float() * 7.999f), a, inst)) g.instances.push_back(inst);
  }
  const float depth = float((plants + uint64_t(side) - 1) / uint64_t(side)) * spacing;
  for (int k = 0; k < 14; ++k) {
    Affine a;
    const float turn = 6.2832f * rng.next_float(), c = std::cos(turn), sn = std::sin(turn);
    a.m = glm::mat3(Vec3(c, 0.0f, -sn), Vec3(0.0f, 1.0f, 0.0f), Vec3(sn, 0.0f, c));
    a.t = Vec3((rng.next_float() - 0.5f) * float(side) * spacing, 0.0f, -depth - 4.0f - 8.0f * rng.next_float());
    Instance inst;
    if (make_instance(8 + uint32_t(k % 2), a, inst)) g.instances.push_back(inst);
  }
  add_quad(*s, Vec3(0.0f, 0.0f, -0.5f * depth), Vec3(0, 1, 0),
           2.5f * std::max(depth, float(side) * spacing) + 60.0f, soil);
  if (flat) {
    flatten_instances(g);
    s->name = "sunflowers-flat";
  }
  // A low sun behind the camera's left shoulder (a point: shadows through the leaves' cut-outs).
  s->lights.push_back(Light{Vec3(-300.0f, 260.0f, 500.0f), Vec3(1.0f, 0.93f, 0.8f), 0.0f});
  s->ambient = default_hemisphere_ambient();
  // Over the heads of the first rows, looking across the field to the trees at its far end.
  s->camera.eye = Vec3(0.8f, 4.2f, 4.0f);
  s->camera.look = Vec3(0.0f, 1.0f, -14.0f);
  s->camera.up = Vec3(0.0f, 1.0f, 0.0f);
  s->camera.fov_deg = 55.0f;
  s->settings.background = Vec3(0.45f, 0.62f, 0.85f);
  finalize_scene(*s);
  return s;
}

}  // namespace frameless
