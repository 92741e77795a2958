// Texture lookups at hits (uv, textured colours, normal and bump maps, alpha cut-outs).
#include "core/scene/texturing.h"

#include <cmath>

#include "core/accel/instance.h"

namespace frameless {

namespace {

uint16_t material_id(const Geometry& g, uint32_t prim) { return g.material_of(prim); }

UvTangent triangle_dpdu(const Geometry& g, uint32_t prim, const Vec3& ng) {
  const UVec3 t = g.triangles[prim];
  const Vec3 e1 = g.positions[t.y] - g.positions[t.x], e2 = g.positions[t.z] - g.positions[t.x];
  if (!g.uvs.empty()) {
    const Vec2 d1 = g.uvs[t.y] - g.uvs[t.x], d2 = g.uvs[t.z] - g.uvs[t.x];
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (std::fabs(det) > 1e-20f) {
      const Vec3 dpdu = (d2.y * e1 - d1.y * e2) / det;
      if (is_finite(dpdu) && glm::dot(dpdu, dpdu) > 0.0f)
        return {dpdu, det < 0.0f ? -1.0f : 1.0f};
    }
  }
  // No usable UVs: any tangent in the plane.
  const Vec3 helper = std::fabs(ng.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  return {glm::cross(helper, ng), 1.0f};
}

// Shading normal from a tangent-space vector (x along dp/du, y along dp/dv, z along n).
Vec3 to_world(const Vec3& t, const Vec3& n, const Vec3& dpdu) {
  Vec3 tu = dpdu - glm::dot(dpdu, n) * n;
  const float len = glm::length(tu);
  if (!(len > 0.0f) || !std::isfinite(len)) return n;
  tu /= len;
  const Vec3 tv = glm::cross(n, tu);
  return t.x * tu + t.y * tv + t.z * n;
}

bool opaque_at(const Scene& scene, const Geometry& g, uint32_t prim, const Ray& ray, float t,
               float u, float v) {
  const MaterialParams& m = scene.materials[material_id(g, prim)];
  float alpha = m.opacity;
  if (m.alpha_tex != kNoTexture) {
    Hit h;
    h.prim = prim;
    h.t = t;
    h.u = u;
    h.v = v;
    TexturePoint at;
    at.uv = hit_uv(g, ray, h);
    at.p = ray.org + t * ray.dir;
    const Vec4 texel = sample_texture(scene.textures[m.alpha_tex], at);
    alpha *= m.alpha_channel == 3 ? texel.w : texel.x;
  }
  return alpha >= m.alpha_cutoff;
}

bool alpha_opaque(const void* ctx, uint32_t prim, const Ray& ray, float t, float u, float v) {
  const Scene& scene = *static_cast<const Scene*>(ctx);
  return opaque_at(scene, scene.geometry, prim, ray, t, u, v);
}

// The same for a shared mesh's own BVH: its rays are in object space, as its geometry.
bool mesh_alpha_opaque(const void* ctx, uint32_t prim, const Ray& ray, float t, float u, float v) {
  const InstancedMesh& mesh = *static_cast<const InstancedMesh*>(ctx);
  return opaque_at(*mesh.scene, mesh.geometry, prim, ray, t, u, v);
}

}  // namespace

Vec2 hit_uv(const Geometry& g, const Ray& ray, const Hit& hit) {
  const uint32_t nt = g.num_triangles();
  if (hit.prim < nt) {
    if (g.uvs.empty()) return Vec2(hit.u, hit.v);
    const UVec3 t = g.triangles[hit.prim];
    const float w0 = 1.0f - hit.u - hit.v;
    return w0 * g.uvs[t.x] + hit.u * g.uvs[t.y] + hit.v * g.uvs[t.z];
  }
  if (hit.prim >= g.first_patch()) return Vec2(hit.u, hit.v);  // the patch's own parameters
  const Sphere& s = g.spheres[hit.prim - nt];
  const Vec3 d = ray.org + hit.t * ray.dir - s.center;
  const float len = glm::length(d);
  if (!(len > 0.0f)) return Vec2(0.0f);
  const Vec3 n = d / len;
  // u grows eastward seen from outside (toward -z from +x), so images are not mirrored.
  const float u = 0.5f + std::atan2(-n.z, n.x) / (2.0f * kPi);
  const float v = std::acos(std::clamp(n.y, -1.0f, 1.0f)) / kPi;
  return Vec2(u, 1.0f - v);
}

UvTangent uv_tangent(const Geometry& g, const Hit& hit, const SurfacePoint& sp) {
  const Vec3 outward = sp.front_face ? sp.ng : -sp.ng;
  UvTangent frame;
  if (hit.prim < g.num_triangles()) {
    frame = triangle_dpdu(g, hit.prim, outward);
  } else if (hit.prim >= g.first_patch() && hit.prim - g.first_patch() < g.patches.size()) {
    Vec3 du, dv;  // dP/du of the patch is the tangent along u
    bezier_eval(g.patches[hit.prim - g.first_patch()].patch(), hit.u, hit.v, &du, &dv);
    frame.dpdu = glm::dot(du, du) > 0.0f ? du : glm::cross(Vec3(0.0f, 1.0f, 0.0f), outward);
    frame.handedness = glm::dot(glm::cross(du, dv), outward) < 0.0f ? -1.0f : 1.0f;
  } else {
    frame.dpdu = glm::cross(Vec3(0.0f, 1.0f, 0.0f), outward);  // along increasing u (eastward)
    if (!(glm::dot(frame.dpdu, frame.dpdu) > 0.0f)) frame.dpdu = Vec3(1.0f, 0.0f, 0.0f);
  }
  return frame;
}

void apply_textures(const Scene& scene, const Geometry& g, const Ray& ray, const Hit& hit,
                    MaterialParams& m, SurfacePoint& sp) {
  TexturePoint at;
  at.uv = hit_uv(g, ray, hit);
  at.p = sp.p;
  const std::vector<Texture>& tex = scene.textures;
  if (m.kd_tex != kNoTexture) m.kd *= Vec3(sample_texture(tex[m.kd_tex], at));
  if (m.emission_tex != kNoTexture) m.emission *= Vec3(sample_texture(tex[m.emission_tex], at));
  if (m.kh_tex != kNoTexture) m.kh *= Vec3(sample_texture(tex[m.kh_tex], at));
  if (m.ks_tex != kNoTexture) m.ks *= Vec3(sample_texture(tex[m.ks_tex], at));
  if (m.normal_tex == kNoTexture && m.bump_tex == kNoTexture) return;
  // The frame is built on the outward normal (uv_tangent), so a surface seen from behind is
  // perturbed the same way as from the front (then turned to the viewer's side below).
  const Vec3 ns_out = sp.front_face ? sp.ns : -sp.ns;
  const UvTangent frame = uv_tangent(g, hit, sp);
  Vec3 n = sp.ns;
  if (m.normal_tex != kNoTexture) {
    // Tangent-space normal map: texel in [0, 1] encodes [-1, 1].
    const Vec4 texel = sample_texture(tex[m.normal_tex], at);
    Vec3 t = 2.0f * Vec3(texel) - Vec3(1.0f);
    t.y *= frame.handedness;
    n = to_world(t, ns_out, frame.dpdu);
  } else {
    // Bump map: the height's finite-difference slopes tilt the normal (Blinn 1978).
    const Texture& b = tex[m.bump_tex];
    const int w = b.image ? std::max(1, b.image->width) : 256;
    const int h = b.image ? std::max(1, b.image->height) : 256;
    const float du = 1.0f / float(w), dv = 1.0f / float(h);
    TexturePoint au = at, av = at;
    au.uv.x += du;
    av.uv.y += dv;
    const float h0 = sample_texture(b, at).x;
    const float su = (sample_texture(b, au).x - h0) / du * m.bump_scale * 0.01f;
    const float sv = (sample_texture(b, av).x - h0) / dv * m.bump_scale * 0.01f;
    n = to_world(Vec3(-su, -sv * frame.handedness, 1.0f), ns_out, frame.dpdu);
  }
  if (!sp.front_face) n = -n;
  const float len = glm::length(n);
  if (!(len > 0.0f) || !std::isfinite(len)) return;
  n /= len;
  // Keep the perturbed normal on the viewer's side of the true surface.
  if (glm::dot(n, sp.ng) <= 0.0f) return;
  sp.ns = n;
}

void apply_textures(const Scene& scene, const Ray& ray, const Hit& hit, MaterialParams& m,
                    SurfacePoint& sp) {
  apply_textures(scene, scene.geometry, ray, hit, m, sp);
}

bool cutout_opaque(const Scene& scene, uint32_t prim, const Ray& ray, float t, float u, float v) {
  return alpha_opaque(&scene, prim, ray, t, u, v);
}

void install_alpha_test(Scene& scene) {
  Accel::AlphaTest test;
  scene.cutout_materials.assign(scene.materials.size(), 0);
  bool any = false;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    scene.cutout_materials[i] = scene.materials[i].cutout() ? 1 : 0;
    any |= scene.cutout_materials[i] != 0;
  }
  if (any) {
    test.ctx = &scene;
    test.masked_material = scene.cutout_materials.data();
    test.opaque = &alpha_opaque;
  }
  scene.accel.set_alpha_test(test);
  // Shared meshes test their own cut-outs in object space, with the scene's materials.
  for (const std::shared_ptr<InstancedMesh>& mesh : scene.geometry.instance_meshes) {
    mesh->scene = &scene;
    Accel::AlphaTest mt;
    if (any) {
      mt.ctx = mesh.get();
      mt.masked_material = scene.cutout_materials.data();
      mt.opaque = &mesh_alpha_opaque;
    }
    mesh->accel.set_alpha_test(mt);
  }
}

}  // namespace frameless
