// Instant global illumination per sample: follow mirrors and glass from the camera to the first
// smooth surface, add its direct light (next-event estimation) and the light of every VPL of the
// pixel's set that it sees, with the geometry term clamped.
#include "core/shading/igi.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/base/rng.h"
#include "core/scene/scene_intersect.h"
#include "core/shading/direct_light.h"
#include "core/shading/light_sampling.h"
#include "core/shading/path_material.h"
#include "core/shading/optics.h"
#include "core/shading/volume_lighting.h"
#include "core/shading/vpl.h"

namespace frameless {
namespace {

// Generations of VPL sets a thread keeps (about 3 MB): a one-shot render's samples of a pixel,
// up to this many, reuse them (past it every sample regenerates its set); the engine's updates
// move through generations and refresh each slot as they pass it.
constexpr uint32_t kGenerations = 256;

struct VplSlot {
  uint64_t set = ~uint64_t(0);
  std::vector<Vpl> vpls;
};

// One render thread's VPL sets; rebuilt when the scene or its settings change.
struct VplCache {
  const Scene* scene = nullptr;
  uint64_t serial = 0;  // the address alone can be a freed scene's
  uint64_t seed = 0;
  int paths = 0, interleave = 0;
  SceneSphere sphere;
  std::vector<VplSlot> slots;
};

// This thread's cache, emptied when the scene or its igi settings change.
VplCache& thread_cache(const Scene& scene) {
  thread_local VplCache cache;
  const IgiSettings& g = scene.settings.igi;
  if (cache.scene != &scene || cache.serial != scene.serial || cache.seed != scene.settings.seed ||
      cache.paths != g.paths || cache.interleave != g.interleave) {
    cache.scene = &scene;
    cache.serial = scene.serial;
    cache.seed = scene.settings.seed;
    cache.paths = g.paths;
    cache.interleave = g.interleave;
    cache.sphere = scene_sphere(scene);
    cache.slots.assign(size_t(kGenerations) * size_t(g.interleave * g.interleave), VplSlot{});
  }
  return cache;
}

// VPL set `set`, generated on first use in its slot.
const std::vector<Vpl>& vpl_set(VplCache& cache, const Scene& scene, const DynamicFrame* frame,
                                uint64_t set) {
  const IgiSettings& g = scene.settings.igi;
  VplSlot& slot = cache.slots[set % cache.slots.size()];
  if (slot.set != set) {
    slot.set = set;
    slot.vpls.clear();
    generate_vpls(scene, frame, cache.sphere, mix64(set ^ scene.settings.seed), g.paths, slot.vpls);
  }
  return slot.vpls;
}

// Indirect light at surface s from the VPLs it sees; the geometry term is clamped to
// 1 / clamp_d2 (what that leaves out near corners is the bias igi accepts).
Vec3 vpl_light(const Scene& scene, const DynamicFrame* frame, const PathSurface& s,
               const Vec3& origin, const std::vector<Vpl>& vpls, float clamp_d2) {
  Vec3 sum(0.0f);
  for (const Vpl& v : vpls) {
    const Vec3 to = v.p - origin;
    const float d2 = glm::dot(to, to);
    if (!(d2 > 0.0f)) continue;
    const float d = std::sqrt(d2);
    const Vec3 wi = to / d;
    const float cx = glm::dot(s.frame.n, wi), cy = -glm::dot(v.n, wi);
    if (cx <= 0.0f || cy <= 0.0f) continue;
    const Vec3 f = path_eval(s, wi);
    const Vec3 c = f * v.power * (cx * cy / (kPi * std::max(d2, clamp_d2)));
    if (!(max_component(c) > 0.0f)) continue;
    Ray r;
    r.org = origin;
    r.dir = wi;
    r.tmin = 0.0f;
    r.tmax = d * (1.0f - 0x1.0p-10f);
    if (!scene_occluded(scene, frame, r)) sum += c;
  }
  return sum;
}

}  // namespace

Vec3 trace_igi(const Scene& scene, const Ray& camera_ray, float px, float py, uint32_t sample_index,
               uint64_t seed, const DynamicFrame* frame, const Hit* known_hit, Hit* first_hit,
               SurfacePoint* first_point, int* bounces, Vec3* first_albedo, Vec3* first_indirect) {
  const IgiSettings& g = scene.settings.igi;
  DirectLight st{scene, frame, LightStrategy::kLightOnly, Rng(seed), environment_emits(scene), false};
  const int n = std::max(1, g.interleave);
  const uint32_t cls = uint32_t(int(std::floor(px)) % n + n * (int(std::floor(py)) % n));
  const uint64_t set = uint64_t(sample_index) * uint64_t(n * n) + cls;
  VplCache& cache = thread_cache(scene);
  const float clamp_d = g.clamp * 2.0f * cache.sphere.radius;
  Vec3 radiance(0.0f), beta(1.0f), extinction(0.0f);
  Ray ray = camera_ray;
  int bounce = 0;
  for (; bounce <= scene.settings.max_depth; ++bounce) {
    Hit hit;
    const bool found = scene_intersect(scene, frame, ray, bounce == 0 ? known_hit : nullptr, hit);
    if (bounce == 0 && first_hit) *first_hit = hit;
    // The volume shader's light on the way, and its shade on what follows.
    if (scene.see_through && !through_volumes(scene, frame, ray, found ? hit.t : kInfinity, radiance, beta)) break;
    if (!found) {  // seen from the camera or through mirrors and glass
      radiance += beta * beer(extinction, kInfinity) *
                  escaped_radiance(scene.environment.get(), scene.settings.background, ray.dir);
      break;
    }
    SurfacePoint sp = scene_surface_point(scene, frame, ray, hit);
    if (max_component(extinction) > 0.0f) beta *= beer(extinction, glm::length(sp.p - ray.org));
    const MaterialParams m = material_at(scene, frame, ray, hit, sp);
    if (bounce == 0 && first_point) *first_point = sp;
    if (bounce == 0 && first_albedo) *first_albedo = guide_albedo(m);
    radiance += beta * m.emission;
    const PathSurface s = make_path_surface(m, sp, -ray.dir);
    const Vec3 origin = offset_ray_origin(sp.p, sp.ng, sp.scale);
    radiance += beta * direct_light(st, s, origin, extinction);
    if (path_is_smooth(s)) {
      const Vec3 indirect = beta * vpl_light(scene, frame, s, origin, vpl_set(cache, scene, frame, set), clamp_d * clamp_d);
      radiance += indirect;
      if (bounce == 0 && first_indirect) *first_indirect = indirect;
      // Polished: the coat's mirror image too, weighted by Schlick (as Whitted does); a glTF
      // coat (GGX of its roughness) is in the BSDF already and sees the VPLs through it.
      if (m.cls != MaterialClass::kPolished || m.roughness >= 0.0f) break;
      const Vec3 ks = schlick(std::clamp(s.wo.z, 0.0f, 1.0f), m.r0);
      Vec3 d = ray.dir - 2.0f * glm::dot(ray.dir, s.frame.n) * s.frame.n;
      if (glm::dot(d, sp.ng) <= 0.0f) break;
      beta *= ks;
      ray.org = origin;
      ray.dir = glm::normalize(d);
    } else {  // mirrors and glass: follow the chosen direction
      PathScatter sc;
      const float u0 = st.rng.next_float(), u1 = st.rng.next_float(), u2 = st.rng.next_float();
      if (!path_sample(s, u0, u1, u2, sc)) break;
      beta *= sc.weight;
      if (sc.transmitted) extinction = s.front_face ? m.extinction : Vec3(0.0f);
      ray.org = sc.transmitted ? offset_ray_origin(sp.p, -sp.ng, sp.scale) : origin;
      ray.dir = sc.wi;
    }
    ray.tmin = 0.0f;
    ray.tmax = kInfinity;
    if (!(max_component(beta) > 0.0f)) break;
  }
  if (bounces) *bounces = bounce;
  return radiance;
}

}  // namespace frameless
