// The path tracer's scattering functions (core/shading/bsdf.h): directional albedo by numerical
// integration (energy conservation, normalisation), the coupled model's coat and base summing to
// one, sampling unbiased against the integral, densities that match what is sampled.
// Statistical checks use fixed seeds and a 5-standard-error bound (two-sided significance
// 6e-7 under the normal approximation).
#include "core/shading/bsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/base/rng.h"
#include "core/shading/optics.h"

namespace frameless {
namespace {

using BrdfFn = std::function<Vec3(const Vec3& wo, const Vec3& wi)>;
using PdfFn = std::function<float(const Vec3& wo, const Vec3& wi)>;
using SampleFn = std::function<BsdfSample(const Vec3& wo, float u1, float u2)>;

Vec3 dir_at(float theta_deg) {
  const float t = theta_deg * kPi / 180.0f;
  return Vec3(std::sin(t), 0.0f, std::cos(t));
}

// The hemisphere integral of g(wi) d(omega) by the midpoint rule in (cos theta, phi), where
// d(omega) = d(cos theta) d(phi).
double hemisphere_integral(const std::function<double(const Vec3&)>& g, int n = 800) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double c = (i + 0.5) / n;
    const double s = std::sqrt(1.0 - c * c);
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = (j + 0.5) / (2 * n) * 2.0 * M_PI;
      sum += g(Vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c)));
    }
  }
  return sum * (1.0 / n) * (2.0 * M_PI / (2 * n));
}

// Directional albedo (red channel): the integral of f cos(theta_i).
double albedo(const BrdfFn& f, const Vec3& wo) {
  return hemisphere_integral([&](const Vec3& wi) { return double(f(wo, wi).x) * wi.z; });
}

// Mean and standard error of the red weight over n samples.
void sampled_albedo(const SampleFn& sample, const Vec3& wo, int n, uint64_t seed, double& mean,
                    double& err) {
  Rng rng(seed);
  double s = 0.0, s2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    const double w = sample(wo, u1, u2).weight.x;
    s += w;
    s2 += w * w;
  }
  mean = s / n;
  err = std::sqrt(std::max(0.0, s2 / n - mean * mean) / n);
}

// Sampling must estimate the albedo without bias, and every sample's density must be the one
// pdf() gives at its direction, with weight = f cos / pdf.
void expect_consistent(const BrdfFn& f, const PdfFn& pdf, const SampleFn& sample, const Vec3& wo,
                       uint64_t seed) {
  const double want = albedo(f, wo);
  double mean = 0, err = 0;
  sampled_albedo(sample, wo, 200000, seed, mean, err);
  EXPECT_NEAR(mean, want, 5.0 * err + 1e-4) << "wo.z " << wo.z;
  Rng rng(seed + 1);
  for (int i = 0; i < 2000; ++i) {
    const BsdfSample s = sample(wo, rng.next_float(), rng.next_float());
    if (!(s.wi.z > 0.0f)) {
      EXPECT_EQ(s.weight, Vec3(0.0f));
      continue;
    }
    EXPECT_NEAR(s.pdf, pdf(wo, s.wi), 1e-3f * s.pdf + 1e-6f);
    const Vec3 expect = f(wo, s.wi) * (s.wi.z / s.pdf);
    EXPECT_NEAR(s.weight.x, expect.x, 1e-4f * expect.x + 1e-6f);
  }
  // The density integrates to at most one over the hemisphere (directions below are lost).
  EXPECT_LE(hemisphere_integral([&](const Vec3& wi) { return double(pdf(wo, wi)); }), 1.0 + 2e-3);
}

TEST(Bsdf, ShadingFrameIsOrthonormalAndRoundTrips) {
  Rng rng(7);
  for (int i = 0; i < 1000; ++i) {
    Vec3 n(rng.next_float() * 2 - 1, rng.next_float() * 2 - 1, rng.next_float() * 2 - 1);
    if (i == 0) n = Vec3(0, 0, -1);  // the basis' one delicate case
    if (glm::length(n) < 1e-3f) continue;
    n = glm::normalize(n);
    const ShadingFrame f = make_shading_frame(n);
    EXPECT_NEAR(glm::dot(f.t, f.b), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(f.t), 1.0f, 1e-5f);
    EXPECT_NEAR(f.to_local(n).z, 1.0f, 1e-5f);
    const Vec3 v(0.3f, -0.5f, 0.8f);
    const Vec3 back = f.to_world(f.to_local(v));
    EXPECT_NEAR(glm::length(back - v), 0.0f, 1e-5f);
  }
}

TEST(Bsdf, LambertReflectsItsAlbedoAndSamplesExactly) {
  const Vec3 rho(0.7f, 0.5f, 0.2f);
  for (float th : {0.0f, 45.0f, 85.0f}) {
    const Vec3 wo = dir_at(th);
    EXPECT_NEAR(albedo([&](const Vec3& o, const Vec3& i) { return lambert_eval(rho, o, i); }, wo),
                0.7, 1e-4);
    Rng rng(3);
    for (int k = 0; k < 100; ++k) {  // f cos / pdf is the albedo for every sample
      const BsdfSample s = lambert_sample(rho, wo, rng.next_float(), rng.next_float());
      EXPECT_NEAR(s.weight.x, rho.x, 1e-5f);
      EXPECT_NEAR(s.weight.z, rho.z, 1e-5f);
    }
  }
  EXPECT_EQ(lambert_eval(rho, dir_at(10), Vec3(0, 0, -1)), Vec3(0.0f));  // no transmission
}

TEST(Bsdf, PhongLobeIsNormalizedAndNeverGainsEnergy) {
  for (float n : {1.0f, 10.0f, 100.0f}) {
    auto f = [&](const Vec3& o, const Vec3& i) { return phong_eval(Vec3(1.0f), n, o, i); };
    // At normal incidence the whole lobe is above the surface: albedo 1 exactly.
    EXPECT_NEAR(albedo(f, dir_at(0)), 1.0, 3e-3) << "N " << n;
    for (float th : {30.0f, 60.0f, 85.0f}) EXPECT_LE(albedo(f, dir_at(th)), 1.0 + 3e-3);
  }
}

TEST(Bsdf, CoupledModelCoatAndBaseSumToOne) {
  // A white base under a Schlick coat of reflectance r0 reflects everything: the coat takes
  // schlick(cos theta_o, r0) and the base, with 21 / (20 pi), the rest.
  for (float r0 : {0.04f, 0.5f}) {
    auto f = [&](const Vec3& o, const Vec3& i) {
      return coupled_diffuse_eval(Vec3(1.0f), Vec3(r0), o, i);
    };
    EXPECT_NEAR(albedo(f, dir_at(0)), 1.0 - r0, 2e-3);
    for (float th : {0.0f, 30.0f, 60.0f, 80.0f, 89.0f}) {
      const Vec3 wo = dir_at(th);
      EXPECT_NEAR(albedo(f, wo) + schlick(wo.z, r0), 1.0, 2e-3) << "r0 " << r0 << " theta " << th;
    }
  }
}

TEST(Bsdf, GgxNeverGainsEnergyAndLosesLittleWhenSmooth) {
  for (float a : {0.2f, 0.5f, 1.0f}) {
    auto f = [&](const Vec3& o, const Vec3& i) { return ggx_eval(Vec3(1.0f), a, o, i); };
    for (float th : {0.0f, 40.0f, 70.0f, 85.0f}) EXPECT_LE(albedo(f, dir_at(th)), 1.0 + 3e-3);
  }
  // Single scattering loses what masking hides: little for a smooth surface seen head on
  // (separable Smith masking: 5.2 % at alpha 0.2), more as the surface gets rougher.
  double last = 1.0;
  for (float a : {0.2f, 0.5f, 1.0f}) {
    auto f = [&](const Vec3& o, const Vec3& i) { return ggx_eval(Vec3(1.0f), a, o, i); };
    const double e = albedo(f, dir_at(0));
    EXPECT_LT(e, last) << "alpha " << a;
    if (a == 0.2f) EXPECT_GT(e, 0.94);
    last = e;
  }
}

TEST(Bsdf, GltfNonMetalCoatAndBaseNeverGainEnergy) {
  // A white base under glTF's 0.04 coat: coat plus base reflect at most what comes in, at every
  // roughness and angle, and most of it (the base keeps what the coat leaves).
  const Vec3 f0(0.04f);
  for (float a : {0.01f, 0.1f, 0.5f, 1.0f}) {
    auto f = [&](const Vec3& o, const Vec3& i) { return ggx_coated_eval(Vec3(1.0f), f0, a, o, i); };
    for (float th : {0.0f, 40.0f, 70.0f, 85.0f}) {
      const double e = albedo(f, dir_at(th));
      EXPECT_LE(e, 1.0 + 3e-3) << "alpha " << a << " theta " << th;
      if (th <= 40.0f) EXPECT_GT(e, 0.9) << "alpha " << a << " theta " << th;
    }
  }
  // The coat alone is the GGX lobe of f0: a black base reflects about 4 % head on.
  auto coat = [&](const Vec3& o, const Vec3& i) { return ggx_coated_eval(Vec3(0.0f), f0, 0.3f, o, i); };
  EXPECT_NEAR(albedo(coat, dir_at(0)), 0.04, 0.01);
}

TEST(Bsdf, SamplingIsUnbiasedAndDensitiesMatch) {
  const Vec3 white(1.0f);
  for (float th : {0.0f, 50.0f, 80.0f}) {
    const Vec3 wo = dir_at(th);
    for (float n : {5.0f, 50.0f}) {
      auto f = [&](const Vec3& o, const Vec3& i) { return phong_eval(white, n, o, i); };
      auto pdf = [&](const Vec3& o, const Vec3& i) { return phong_pdf(n, o, i); };
      auto sample = [&](const Vec3& o, float u1, float u2) {
        return phong_sample(white, n, o, u1, u2);
      };
      expect_consistent(f, pdf, sample, wo, 11);
    }
    for (float a : {0.3f, 0.7f}) {
      auto f = [&](const Vec3& o, const Vec3& i) { return ggx_eval(white, a, o, i); };
      auto pdf = [&](const Vec3& o, const Vec3& i) { return ggx_pdf(a, o, i); };
      auto sample = [&](const Vec3& o, float u1, float u2) {
        return ggx_sample(white, a, o, u1, u2);
      };
      expect_consistent(f, pdf, sample, wo, 23);
    }
    for (float a : {0.05f, 0.5f}) {  // glTF's non-metals: the lobe is picked by a third number
      const Vec3 kd(0.7f), f0(0.04f);
      Rng pick(31);
      auto f = [&](const Vec3& o, const Vec3& i) { return ggx_coated_eval(kd, f0, a, o, i); };
      auto pdf = [&](const Vec3& o, const Vec3& i) { return ggx_coated_pdf(f0, a, o, i); };
      auto sample = [&](const Vec3& o, float u1, float u2) {
        return ggx_coated_sample(kd, f0, a, o, pick.next_float(), u1, u2);
      };
      expect_consistent(f, pdf, sample, wo, 29);
    }
  }
}

}  // namespace
}  // namespace frameless
