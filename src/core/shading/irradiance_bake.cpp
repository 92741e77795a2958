// The irradiance volume's bake: paths from every grid vertex, projected on harmonics.
#include "core/shading/irradiance_bake.h"

#include <chrono>
#include <cmath>
#include <memory>

#include "core/base/rng.h"
#include "core/base/sobol.h"
#include "core/geometry/geometry.h"
#include "core/shading/bsdf.h"
#include "core/shading/path_tracer.h"

namespace frameless {

double bake_irradiance_volume(Scene& scene) {
  const auto t0 = std::chrono::steady_clock::now();
  Ambient& a = scene.ambient;
  auto v = std::make_shared<IrradianceVolume>();
  Vec3 lo, hi;
  if (!geometry_bounds(scene.geometry, lo, hi)) lo = Vec3(-1.0f), hi = Vec3(1.0f);
  const Vec3 ext = glm::max(hi - lo, Vec3(1e-6f));
  const float longest = std::max(ext.x, std::max(ext.y, ext.z));
  const auto cells = [&](float e) { return std::max(1, int(std::lround(float(a.volume_resolution) * e / longest))); };
  v->lo = lo;
  v->hi = lo + ext;
  v->nx = cells(ext.x), v->ny = cells(ext.y), v->nz = cells(ext.z);
  const size_t n = size_t(v->nx) * size_t(v->ny) * size_t(v->nz);
  v->sh.assign(n, {});
  v->valid.assign(n, 1);
  // Cosine-lobe convolution of each band (Ramamoorthi and Hanrahan 2001).
  const float band[9] = {kPi, 2.0f * kPi / 3.0f, 2.0f * kPi / 3.0f, 2.0f * kPi / 3.0f, kPi / 4.0f,
                         kPi / 4.0f,  kPi / 4.0f, kPi / 4.0f, kPi / 4.0f};
  const int m = a.volume_samples;
  for (int k = 0; k < v->nz; ++k)
    for (int j = 0; j < v->ny; ++j)
      for (int i = 0; i < v->nx; ++i) {
        const size_t idx = v->index(i, j, k);
        std::array<Vec3, 9> l{};
        int back = 0;
        for (int s = 0; s < m; ++s) {
          float u1, u2;  // stratified directions (Owen-scrambled Sobol')
          owen_sobol_2d(uint32_t(s), mix64(idx ^ scene.settings.seed), u1, u2);
          Ray ray;
          ray.org = v->vertex(i, j, k);
          ray.dir = sample_uniform_sphere(u1, u2);
          SurfacePoint sp;
          Hit hit;
          const Vec3 radiance = trace_path(scene, ray, mix64(idx << 20 | uint64_t(s)), nullptr, nullptr, &hit, &sp);
          if (hit.valid() && !sp.front_face) ++back;
          const std::array<float, 9> y = sh_basis(ray.dir);
          if (is_finite(radiance))
            for (int b = 0; b < 9; ++b) l[size_t(b)] += radiance * y[size_t(b)];
        }
        for (int b = 0; b < 9; ++b) v->sh[idx][size_t(b)] = l[size_t(b)] * (4.0f * kPi / float(m)) * band[b];
        v->valid[idx] = back * 10 <= m * 4;
      }
  a.volume = std::move(v);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace frameless
