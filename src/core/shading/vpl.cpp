// Light paths for instant global illumination: started quasi-randomly (Halton) at a light, traced
// through mirrors and glass, leaving a VPL at every smooth surface, ended by Russian roulette.
#include "core/shading/vpl.h"

#include <algorithm>
#include <cmath>

#include "core/base/rng.h"
#include "core/geometry/shading_frame.h"
#include "core/scene/scene_intersect.h"
#include "core/shading/bsdf.h"
#include "core/shading/direct_light.h"
#include "core/shading/light_sampling.h"
#include "core/shading/path_material.h"

namespace frameless {
namespace {

constexpr int kMaxLightBounces = 8;

// Radical inverse of i in a prime base (the Halton sequence's dimension for that base).
float radical_inverse(uint64_t i, uint32_t base) {
  const double inv = 1.0 / base;
  double f = inv, r = 0.0;
  for (; i; i /= base, f *= inv) r += double(i % base) * f;
  return float(std::min(r, 0x1.fffffep-1));
}

// A point on the unit disk (polar mapping).
Vec2 unit_disk(float u1, float u2) {
  const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
  return Vec2(r * std::cos(phi), r * std::sin(phi));
}

// The albedo a smooth surface reflects a VPL's light with (Lambertian reading of its base; glTF
// materials, which carry a roughness, have a coat of r0 over it too).
Vec3 vpl_albedo(const MaterialParams& m) {
  return m.cls == MaterialClass::kPolished || m.roughness >= 0.0f ? m.kd * (Vec3(1.0f) - m.r0) : m.kd;
}

// A light path's start: its ray and the flux it carries (for Parker's point lights the flux
// depends on where the ray lands: `per_d2` is multiplied by the squared distance then).
struct Start {
  Ray ray;
  Vec3 flux{0.0f};
  bool per_d2 = false;
};

}  // namespace

SceneSphere scene_sphere(const Scene& scene) {
  SceneSphere s;
  Vec3 lo, hi;
  if (geometry_bounds(scene.geometry, lo, hi)) {
    s.center = 0.5f * (lo + hi);
    s.radius = std::max(1e-6f, 0.5f * glm::length(hi - lo));
  }
  return s;
}

void generate_vpls(const Scene& scene, const DynamicFrame* frame, const SceneSphere& sphere,
                   uint64_t set, int paths, std::vector<Vpl>& out) {
  const std::vector<Light>& lights = frame_lights(scene, frame);
  const bool emitters = !scene.emitters.empty();
  const bool environment = environment_emits(scene);
  const int groups = int(lights.size()) + (emitters ? 1 : 0) + (environment ? 1 : 0);
  if (groups == 0 || paths <= 0) return;
  for (int j = 0; j < paths; ++j) {
    const uint64_t index = set * uint64_t(paths) + uint64_t(j);
    const float u[5] = {radical_inverse(index, 2), radical_inverse(index, 3), radical_inverse(index, 5),
                        radical_inverse(index, 7), radical_inverse(index, 11)};
    Rng rng(mix64(index ^ 0x766c70ull));
    const int g = std::min(int(u[0] * float(groups)), groups - 1);
    const float scale = float(groups) / float(paths);  // 1 / (group probability x path count)
    Start st;
    st.ray.tmin = 0.0f;
    if (g < int(lights.size())) {
      const Light& l = lights[size_t(g)];
      if (l.kind == LightKind::kDirectional) {  // a disk across the scene, light along l.direction
        const ShadingFrame f = make_shading_frame(l.direction);
        const Vec2 d = unit_disk(u[1], u[2]) * sphere.radius;
        st.ray.org = sphere.center - l.direction * (2.0f * sphere.radius) + f.t * d.x + f.b * d.y;
        st.ray.dir = l.direction;
        st.flux = kPi * l.color * (kPi * sphere.radius * sphere.radius) * scale;
      } else {  // Parker's irradiance pi l_e at any distance: flux grows with d^2 (light_sampling.h)
        st.ray.org = l.position;
        st.ray.dir = sample_uniform_sphere(u[1], u[2]);
        st.flux = 4.0f * kPi * kPi * l.color * scale;
        st.per_d2 = true;
      }
    } else if (emitters && g == int(lights.size())) {
      const EmitterTable& t = scene.emitters;
      const uint32_t i = t.pick(u[1]);
      const float pmf = t.pmf(i);
      if (!(pmf > 0.0f)) continue;
      const Geometry& geo = scene.geometry;
      const TrianglePoint tp = triangle_point(scene, t.prims[i], u[2], u[3]);
      const Vec3 n = rng.next_float() < 0.5f ? -tp.n : tp.n;  // both sides emit
      const uint16_t id = t.prims[i] < geo.triangle_material.size() ? geo.triangle_material[t.prims[i]] : 0;
      const Vec3 le = frame_material(scene, frame, id).emission;
      st.ray.org = offset_ray_origin(tp.p, n, tp.scale);
      st.ray.dir = make_shading_frame(n).to_world(sample_cosine_hemisphere(u[4], rng.next_float()));
      st.flux = le * (2.0f * kPi * t.area[i] / pmf) * scale;  // L pi A x 2 sides / pmf
    } else {  // the environment: towards a sampled direction, from a disk outside everything
      LightSample ls;
      if (!sample_environment(scene, u[1], u[2], ls)) continue;
      const ShadingFrame f = make_shading_frame(ls.wi);
      const Vec2 d = unit_disk(u[3], u[4]) * sphere.radius;
      st.ray.org = sphere.center + ls.wi * (2.0f * sphere.radius) + f.t * d.x + f.b * d.y;
      st.ray.dir = -ls.wi;
      st.flux = ls.radiance * (kPi * sphere.radius * sphere.radius / ls.pdf) * scale;
    }
    Vec3 flux = st.flux;
    Ray ray = st.ray;
    ray.tmax = kInfinity;
    for (int bounce = 0; bounce < kMaxLightBounces; ++bounce) {
      Hit hit;
      if (!scene_intersect(scene, frame, ray, hit)) break;
      SurfacePoint sp = scene_surface_point(scene, frame, ray, hit);
      if (bounce == 0 && st.per_d2) flux *= glm::dot(sp.p - ray.org, sp.p - ray.org);
      const MaterialParams m = material_at(scene, frame, ray, hit, sp);
      const PathSurface s = make_path_surface(m, sp, -ray.dir);
      if (path_is_smooth(s) && m.cls != MaterialClass::kMetal) {  // metals pass light on
        const Vec3 albedo = vpl_albedo(m);
        out.push_back(Vpl{sp.p, sp.ng, flux * albedo});
        // Roulette by the albedo, then a cosine-weighted bounce.
        const float q = std::min(1.0f, max_component(albedo));
        if (!(rng.next_float() < q)) break;
        flux *= albedo / q;
        ray.org = offset_ray_origin(sp.p, sp.ng, sp.scale);
        ray.dir = s.frame.to_world(sample_cosine_hemisphere(rng.next_float(), rng.next_float()));
        if (glm::dot(ray.dir, sp.ng) <= 0.0f) break;
      } else {  // mirrors and glass pass the light on (caustic light paths)
        PathScatter sc;
        const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
        if (!path_sample(s, u0, u1, u2, sc)) break;
        flux *= sc.weight;
        ray.org = offset_ray_origin(sp.p, sc.transmitted ? -sp.ng : sp.ng, sp.scale);
        ray.dir = sc.wi;
      }
      ray.tmin = 0.0f;
      ray.tmax = kInfinity;
      if (!is_finite(flux) || !(max_component(flux) > 0.0f)) break;
    }
  }
}

}  // namespace frameless
