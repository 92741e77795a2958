// Light slab baking: one sheared pinhole view per uv node, stratified samples per st texel.
#include "core/shading/lightfield_bake.h"

#include <Imath/half.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/base/rng.h"
#include "core/shading/render_sample.h"

namespace frameless {

bool slab_around_scene(const Scene& scene, Affine& slab) {
  Vec3 lo(kInfinity), hi(-kInfinity);
  Vec3 glo, ghi;
  if (geometry_bounds(scene.geometry, glo, ghi)) lo = glm::min(lo, glo), hi = glm::max(hi, ghi);
  for (const VolumeObject& v : scene.volumes) lo = glm::min(lo, v.lo), hi = glm::max(hi, v.hi);
  if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return false;
  const Vec3 centre = 0.5f * (lo + hi);
  const float radius = std::max(0.5f * glm::length(hi - lo) * 1.01f, 1e-6f);
  Vec3 z = scene.camera.eye - centre;
  z = glm::length(z) > 0.0f ? glm::normalize(z) : Vec3(0.0f, 0.0f, 1.0f);
  Vec3 x = glm::cross(scene.camera.up, z);
  if (!(glm::length(x) > 1e-6f)) x = glm::cross(std::abs(z.y) < 0.9f ? Vec3(0, 1, 0) : Vec3(1, 0, 0), z);
  x = glm::normalize(x);
  const Vec3 y = glm::cross(z, x);
  slab.m = glm::mat3(radius * x, radius * y, radius * z);
  slab.t = centre;
  return true;
}

CameraBasis lightfield_view(const Affine& slab, const LightField& lf, uint32_t i, uint32_t j) {
  // camera_direction = w + sx u + sy v with sx, sy in [-1, 1] across the image: the line from the
  // uv node through st point (sx, sy, 0) of the slab.
  CameraBasis b;
  b.eye = slab.point(Vec3(lf.u_of(i), lf.v_of(j), 1.0f));
  b.w = slab.t - b.eye;
  b.u = slab.vector(Vec3(1.0f, 0.0f, 0.0f));
  b.v = slab.vector(Vec3(0.0f, 1.0f, 0.0f));
  b.tan_half = 1.0f;
  b.aspect = 1.0f;
  b.width = int(lf.ns);
  b.height = int(lf.nt);
  return b;
}

namespace {

void bake_view(const Scene& scene, const Affine& slab, LightField& lf, int spp, uint32_t view) {
  const uint32_t i = view % lf.nu, j = view / lf.nu;
  const CameraBasis b = lightfield_view(slab, lf, i, j);
  const int g = std::max(1, int(std::ceil(std::sqrt(double(spp)))));
  for (uint32_t y = 0; y < lf.nt; ++y)
    for (uint32_t x = 0; x < lf.ns; ++x) {
      Vec3 sum(0.0f);
      int hits = 0;
      for (int k = 0; k < spp; ++k) {
        const float px = float(x) + (float(k % g) + 0.5f) / float(g);
        const float py = float(y) + (float((k / g) % g) + 0.5f) / float(g);
        const uint64_t seed = sample_seed(x + lf.ns * i, y + lf.nt * j, uint32_t(k), scene.settings.seed);
        const SampleResult r = trace_sample(scene, b, px, py, seed, nullptr, nullptr, uint32_t(k));
        if (!r.valid || r.object == kPointSky) continue;
        sum += r.color;
        ++hits;
      }
      const Vec3 c = sum / float(spp);
      uint16_t* p = lf.rgba.data() + lf.texel_offset(i, j, x, lf.nt - 1 - y);
      p[0] = imath_float_to_half(c.x);
      p[1] = imath_float_to_half(c.y);
      p[2] = imath_float_to_half(c.z);
      p[3] = imath_float_to_half(float(hits) / float(spp));
    }
}

}  // namespace

LightField bake_lightfield(const Scene& scene, const Affine& slab, const LightfieldBakeOptions& o,
                           const ParallelFor& pf) {
  LightField lf;
  lf.nu = o.nu, lf.nv = o.nv, lf.ns = o.ns, lf.nt = o.nt;
  lf.slab_to_model = slab;
  lf.source = scene.name;
  lf.rgba.assign(size_t(lf.width()) * lf.height() * 4, 0);
  const uint32_t views = o.nu * o.nv;
  std::atomic<uint32_t> done{0};
  const int spp = std::max(1, o.spp);
  parallel_for_each(pf, views, [&](size_t v) {
    bake_view(scene, slab, lf, spp, uint32_t(v));  // each view writes its own tile
    const uint32_t n = done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (o.progress) o.progress(double(n) / views);
  });
  return lf;
}

}  // namespace frameless
