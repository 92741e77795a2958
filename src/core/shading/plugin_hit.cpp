// The plug-in shader's view of a hit and the host calls shared by every integrator.
#include "core/shading/plugin_hit.h"

#include <cmath>

#include "core/scene/texturing.h"

namespace frameless {

fl_hit make_plugin_hit(const Scene& scene, const Ray& ray, const Hit& hit, const SurfacePoint& sp, int depth) {
  const bool plain = hit.inst == kInvalidId && !is_dynamic_prim(hit.prim) && !is_volume_prim(hit.prim);
  const Vec2 uv = plain ? hit_uv(scene.geometry, ray, hit) : Vec2(0.0f);
  // The tangent frame of the UVs, orthogonalised against the shading normal.
  const UvTangent f = plain ? uv_tangent(scene.geometry, hit, sp) : UvTangent{};
  Vec3 t = f.dpdu - glm::dot(f.dpdu, sp.ns) * sp.ns;
  if (!(glm::length(t) > 1e-12f) || !is_finite(t)) {
    const Vec3 helper = std::fabs(sp.ns.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    t = glm::cross(helper, sp.ns);
  }
  t = glm::normalize(t);
  const Vec3 b = glm::cross(sp.ns, t) * (sp.front_face ? f.handedness : -f.handedness);
  fl_hit h{};
  h.position = to_fl(sp.p);
  h.geometric_normal = to_fl(sp.ng);
  h.shading_normal = to_fl(sp.ns);
  h.direction = to_fl(ray.dir);
  h.u = uv.x;
  h.v = uv.y;
  h.front_face = sp.front_face ? 1 : 0;
  h.depth = depth;
  h.tangent = to_fl(t);
  h.bitangent = to_fl(b);
  return h;
}

float plugin_noise(fl_vec3 p) {
  const Vec3 q = from_fl(p);
  return is_finite(q) ? perlin_noise(q) : 0.0f;
}

float plugin_turbulence(fl_vec3 p, int octaves) {
  const Vec3 q = from_fl(p);
  return is_finite(q) && octaves > 0 ? turbulence(q, std::min(octaves, 16)) : 0.0f;
}

fl_vec4 plugin_texture(const Scene& scene, float slot, float u, float v, fl_vec3 p) {
  if (!(slot >= 0.0f) || !(slot < float(scene.textures.size()))) return fl_vec4{0, 0, 0, 0};
  TexturePoint at;
  at.uv = Vec2(std::isfinite(u) ? u : 0.0f, std::isfinite(v) ? v : 0.0f);
  at.p = is_finite(from_fl(p)) ? from_fl(p) : Vec3(0.0f);
  const Vec4 c = sample_texture(scene.textures[size_t(slot)], at);
  return fl_vec4{c.x, c.y, c.z, c.w};
}

namespace {

const Scene& scene_of(void* ctx) { return *static_cast<const Scene*>(ctx); }
void no_lights(void*, fl_light_visitor, void*) {}
fl_vec3 no_ambient(void*, fl_vec3) { return fl_vec3{0, 0, 0}; }
fl_vec3 no_trace(void*, fl_vec3, fl_vec3) { return fl_vec3{0, 0, 0}; }
float no_random(void*) { return 0.0f; }
fl_vec4 scene_texture(void* ctx, float slot, float u, float v, fl_vec3 p) { return plugin_texture(scene_of(ctx), slot, u, v, p); }

}  // namespace

fl_host path_plugin_host(const Scene& scene) {
  return fl_host{FRAMELESS_SHADER_API_VERSION, const_cast<Scene*>(&scene), &no_lights, &no_ambient, &no_trace,
                 &no_random, &plugin_noise, &plugin_turbulence, &scene_texture};
}

}  // namespace frameless
