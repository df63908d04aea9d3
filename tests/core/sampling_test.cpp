// Sampling functions integrate to what they should: Monte Carlo estimates of
// known integrals with their densities, and BSDF samples that agree with the
// BSDF's own evaluation (weight = f cos / pdf) and conserve energy.
#include "math/rng.h"
#include "math/sampling.h"
#include "scene/bsdf.h"
#include "shading/lobes.h"
#include "shading/microfacet.h"
#include "scene/light.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

namespace ppm {
namespace {

constexpr int kN = 400000;

TEST(Sampling, CosineHemisphereIntegratesCosine) {
  // E[cos / pdf] over the hemisphere = integral of cos = pi.
  Rng rng(1, 1, 1);
  double sum = 0.0, max_dev = 0.0;
  for (int i = 0; i < kN; ++i) {
    const Vec3 w = sample_cosine_hemisphere(rng.uniform(), rng.uniform());
    max_dev = std::fmax(max_dev, std::fabs(glm::length(w) - 1.0));
    ASSERT_GE(w.z, 0.0);
    sum += kPi * w.z;  // integral of cos^2 over the hemisphere: E[cos^2 / (cos/pi)] = 2 pi / 3
  }
  EXPECT_NEAR(sum / kN, 2.0 * kPi / 3.0, 0.01);
  EXPECT_LT(max_dev, 1e-12);
}

TEST(Sampling, UniformSphereAndConeAreUniform) {
  Rng rng(2, 2, 2);
  double z_sum = 0.0, z2_sum = 0.0;
  for (int i = 0; i < kN; ++i) {
    const Vec3 w = sample_uniform_sphere(rng.uniform(), rng.uniform());
    z_sum += w.z;
    z2_sum += w.z * w.z;
  }
  EXPECT_NEAR(z_sum / kN, 0.0, 0.005);
  EXPECT_NEAR(z2_sum / kN, 1.0 / 3.0, 0.005);
  const double cos_max = std::cos(0.3);
  double inside = 0.0;
  for (int i = 0; i < kN; ++i) {
    const Vec3 w = sample_uniform_cone(rng.uniform(), rng.uniform(), cos_max);
    ASSERT_GE(w.z, cos_max - 1e-12);
    inside += w.z > std::cos(0.15);  // fraction of the solid angle inside half the angle
  }
  EXPECT_NEAR(inside / kN, (1.0 - std::cos(0.15)) / (1.0 - cos_max), 0.005);
}

TEST(Sampling, DiskAndTriangleAreUniform) {
  Rng rng(3, 3, 3);
  double r2 = 0.0, inner = 0.0;
  for (int i = 0; i < kN; ++i) {
    const Vec2 d = sample_uniform_disk(rng.uniform(), rng.uniform());
    ASSERT_LE(glm::length(d), 1.0 + 1e-12);
    r2 += glm::dot(d, d);
    inner += d.x > 0.5;
  }
  EXPECT_NEAR(r2 / kN, 0.5, 0.003);  // E[r^2] = 1/2 for a uniform disk
  const double seg = (std::acos(0.5) - 0.5 * std::sqrt(0.75)) / kPi;  // area of the cap x > 0.5, over pi
  EXPECT_NEAR(inner / kN, seg, 0.003);
  double b1 = 0.0, b2 = 0.0;
  for (int i = 0; i < kN; ++i) {
    const Vec2 b = sample_uniform_triangle(rng.uniform(), rng.uniform());
    ASSERT_GE(b.x, 0.0);
    ASSERT_GE(b.y, 0.0);
    ASSERT_LE(b.x + b.y, 1.0 + 1e-12);
    b1 += b.x;
    b2 += b.y;
  }
  EXPECT_NEAR(b1 / kN, 1.0 / 3.0, 0.003);
  EXPECT_NEAR(b2 / kN, 1.0 / 3.0, 0.003);
}

SurfacePoint flat_point(const Color& albedo) { return SurfacePoint{Vec3(0, 0, 1), Vec3(0, 0, 1), albedo}; }

// Albedo by sampling (mean weight) must match albedo by integrating f cos over
// uniform hemisphere directions.
void check_albedo_agrees(const Material& m, const Vec3& wo, double tol) {
  const SurfacePoint sp = flat_point(m.base_color);
  Rng rng(4, 4, 4);
  double sampled = 0.0, integrated = 0.0;
  for (int i = 0; i < kN; ++i) {
    BsdfSample s;
    if (bsdf_sample(m, sp, wo, rng.uniform(), rng.uniform(), rng.uniform(), 0.0, false, s) && s.wi.z > 0.0)
      sampled += s.weight.x;
    // Reference: the same integral with an independent density (uniform over the hemisphere,
    // 8 stratified samples per draw to tame the variance of peaked lobes).
    for (int k = 0; k < 8; ++k) {
      const Vec3 wi = sample_uniform_cone((k + rng.uniform()) / 8.0, rng.uniform(), 0.0);
      integrated += bsdf_eval(m, sp, wo, wi).x * wi.z * 2.0 * kPi / 8.0;
    }
  }
  EXPECT_NEAR(sampled / kN, integrated / kN, tol) << "roughness " << m.roughness;
  EXPECT_LE(sampled / kN, 1.0 + tol);
}

TEST(Bsdf, DiffuseSampleMatchesEval) {
  Material m;
  m.base_color = Color(0.6);
  check_albedo_agrees(m, glm::normalize(Vec3(0.3, 0.1, 1.0)), 0.01);
}

TEST(Bsdf, RoughMetalSampleMatchesEval) {
  for (double roughness : {0.2, 0.5, 0.9}) {
    Material m;
    m.kind = MaterialKind::Metal;
    m.base_color = Color(0.9);
    m.roughness = roughness;
    check_albedo_agrees(m, glm::normalize(Vec3(0.5, 0.0, 1.0)), 0.02);
  }
}

TEST(Bsdf, SmoothGlassConservesEnergyAndObeysSnell) {
  Material m;
  m.kind = MaterialKind::Glass;
  m.base_color = Color(1.0);
  m.ior = 1.5;
  const SurfacePoint sp = flat_point(m.base_color);
  const Vec3 wo = glm::normalize(Vec3(std::sin(0.6), 0.0, std::cos(0.6)));
  BsdfSample b[2];
  // Eye paths: the reflected and refracted shares add up to one.
  ASSERT_EQ(specular_branches(m, sp, wo, 0.5, 0.5, 0.5, 0.5, b), 2);
  EXPECT_NEAR(b[0].weight.x + b[1].weight.x, 1.0, 1e-12);
  // Photons follow Cycles' rule: refraction into glass divides by eta^2, out of it multiplies.
  const DielectricParams glass{m.ior, 0.0, Color(1.0), m.base_color};
  BsdfSample p[2];
  ASSERT_EQ(dielectric_branches(glass, sp, wo, true, p), 2);
  EXPECT_NEAR(p[1].weight.x, b[1].weight.x / (1.5 * 1.5), 1e-12);
  EXPECT_NEAR(p[0].weight.x, b[0].weight.x, 1e-12);
  const Vec3 out_wo = glm::normalize(Vec3(0.2, 0.0, -1.0));  // from inside, no total internal reflection
  BsdfSample o[2], op[2];
  ASSERT_EQ(specular_branches(m, sp, out_wo, 0.5, 0.5, 0.5, 0.5, o), 2);
  ASSERT_EQ(dielectric_branches(glass, sp, out_wo, true, op), 2);
  EXPECT_NEAR(op[1].weight.x, o[1].weight.x * 1.5 * 1.5, 1e-12);
  const double sin_t = std::sqrt(b[1].wi.x * b[1].wi.x + b[1].wi.y * b[1].wi.y);
  EXPECT_NEAR(std::sin(0.6), 1.5 * sin_t, 1e-12);
  EXPECT_LT(b[1].wi.z, 0.0);
  // From inside at a grazing angle: total internal reflection, one branch of weight 1.
  const Vec3 inside = glm::normalize(Vec3(std::sin(1.2), 0.0, -std::cos(1.2)));
  ASSERT_EQ(specular_branches(m, sp, inside, 0.5, 0.5, 0.5, 0.5, b), 1);
  EXPECT_DOUBLE_EQ(b[0].weight.x, 1.0);
  // Normal incidence: F = ((n-1)/(n+1))^2.
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, 1.5), 0.04, 1e-12);
}

TEST(Lights, SpotFluxIntegratesIntensity) {
  // A spot with full 180-degree cone and no blend emits half a point light's flux.
  Light l;
  l.kind = LightKind::Spot;
  l.power = Color(100.0);
  l.cos_half_spot = std::cos(kPi / 2.0);
  prepare_light(l, Aabb{Vec3(-1.0), Vec3(1.0)});
  EXPECT_NEAR(l.flux.x, 50.0, 0.05);
  // Photon weights average to the flux.
  Rng rng(5, 5, 5);
  l.cos_half_spot = std::cos(0.5);
  l.spot_smooth = (1.0 - l.cos_half_spot) * 0.3;
  prepare_light(l, Aabb{Vec3(-1.0), Vec3(1.0)});
  double sum = 0.0;
  for (int i = 0; i < kN; ++i)
    sum += emit_photon(l, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()).flux.x;
  EXPECT_NEAR(sum / kN / l.flux.x, 1.0, 0.01);
}

TEST(Lights, AreaLightDirectMatchesAnalyticIrradiance) {
  // A disk light of radiance L and radius a seen on-axis from distance h gives
  // irradiance E = pi L a^2 / (h^2 + a^2).
  Light l;
  l.kind = LightKind::Disk;
  l.power = Color(10.0);
  l.position = Vec3(0, 0, 2.0);
  l.direction = Vec3(0, 0, -1);
  l.axis_u = Vec3(0.5, 0, 0);
  l.axis_v = Vec3(0, 0.5, 0);
  prepare_light(l, Aabb{Vec3(-1.0), Vec3(1.0)});
  Rng rng(6, 6, 6);
  double e = 0.0;
  for (int i = 0; i < kN; ++i) {
    DirectSample ds;
    if (sample_direct(l, Vec3(0.0), Vec3(0, 0, 1), rng.uniform(), rng.uniform(), ds)) e += ds.value.x * ds.wi.z;
  }
  const double L = l.radiance.x, a = 0.5, h = 2.0;
  EXPECT_NEAR(e / kN, kPi * L * a * a / (h * h + a * a), 0.005 * kPi * L * a * a / (h * h));
}

TEST(Lights, TheDensityOfTheirDirectionsIsWhatTheirSamplesCarry) {
  // For lights with a density (light_has_pdf), a sample's value times the density of its direction
  // is the radiance a ray along it sees (light_seen, the sun's disc), at the sample's distance.
  const Aabb box{Vec3(-1.0), Vec3(1.0)};
  std::vector<Light> lights(4);
  lights[0].kind = LightKind::Sphere;
  lights[0].radius = 0.3;
  lights[1].kind = LightKind::Rectangle;
  lights[1].axis_u = 0.4 * glm::normalize(Vec3(1.0, 0.0, 0.1));  // in the plane normal to `direction` below
  lights[1].axis_v = Vec3(0.0, 0.2, 0.0);
  lights[2] = lights[1];
  lights[2].kind = LightKind::Disk;
  lights[3].kind = LightKind::Sun;
  lights[3].cos_sun = std::cos(0.1);
  for (Light& l : lights) {
    l.power = Color(50.0, 20.0, 10.0);
    l.position = Vec3(0.2, 0.1, 3.0);
    l.direction = glm::normalize(Vec3(0.1, 0.0, -1.0));
    prepare_light(l, box);
    ASSERT_TRUE(light_has_pdf(l));
  }
  const Vec3 p(0.0, 0.0, 0.0);
  Rng rng(8, 8, 8);
  for (const Light& l : lights)
    for (int i = 0; i < 200; ++i) {
      DirectSample ds;
      if (!sample_light_with_pdf(l, p, rng.uniform(), rng.uniform(), ds)) continue;
      const double pdf = light_pdf(l, p, ds.wi);
      ASSERT_GT(pdf, 0.0);
      double t = kInf;
      const Color seen = l.kind == LightKind::Sun ? l.radiance : light_seen(l, Ray{p, ds.wi}, kInf, t);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(ds.value[c] * pdf, seen[c], 1e-6 * seen[c]);
      if (l.kind != LightKind::Sun) EXPECT_NEAR(t, ds.distance, 1e-9);
    }
  // Directions a light never draws have no density; lights of no size have none at all.
  EXPECT_EQ(light_pdf(lights[0], p, Vec3(0.0, 0.0, -1.0)), 0.0);
  EXPECT_EQ(light_pdf(lights[3], p, Vec3(1.0, 0.0, 0.0)), 0.0);
  Light point;
  EXPECT_FALSE(light_has_pdf(point));
}

}  // namespace
}  // namespace ppm

namespace ppm {
namespace {

// Rough glass: the sampled weights (reflection + transmission) conserve energy
// and agree with integrating f |cos| over the whole sphere.
TEST(Bsdf, RoughGlassSampleMatchesEvalAndConservesEnergy) {
  for (double roughness : {0.3, 0.6}) {
    for (double cos_o : {0.9, 0.4, -0.7}) {  // negative: from inside the glass
      Material m;
      m.kind = MaterialKind::Glass;
      m.base_color = Color(1.0);
      m.ior = 1.5;
      m.roughness = roughness;
      const SurfacePoint sp{Vec3(0, 0, 1), Vec3(0, 0, 1), m.base_color};
      const Vec3 wo = glm::normalize(Vec3(std::sqrt(1 - cos_o * cos_o), 0.0, cos_o));
      Rng rng(9, 9, 9);
      // Split by side: reflection (same side as wo) and transmission.
      double sampled_r = 0.0, sampled_t = 0.0, eval_r = 0.0, eval_t = 0.0;
      const int n = test_samples(300000);
      for (int i = 0; i < n; ++i) {
        BsdfSample s;
        if (bsdf_sample(m, sp, wo, rng.uniform(), rng.uniform(), rng.uniform(), 0.0, true, s))
          (s.wi.z * wo.z > 0.0 ? sampled_r : sampled_t) += s.weight.x;
        for (int k = 0; k < 8; ++k) {
          const Vec3 wi = sample_uniform_sphere((k + rng.uniform()) / 8.0, rng.uniform());
          const double v = bsdf_eval(m, sp, wo, wi).x * std::fabs(wi.z) * 4.0 * kPi / 8.0;
          (wi.z * wo.z > 0.0 ? eval_r : eval_t) += v;
        }
      }
      const std::string where = "roughness " + std::to_string(roughness) + ", cos_o " + std::to_string(cos_o);
      // Energy, without the factor (eta_o / eta_i)^2 photons carry through refraction (Cycles' rule).
      const double eta_o = wo.z > 0.0 ? 1.0 : m.ior, eta_i = wo.z > 0.0 ? m.ior : 1.0;
      const double energy = (sampled_r + sampled_t * (eta_i / eta_o) * (eta_i / eta_o)) / n;
      EXPECT_LE(energy, 1.0 + 1e-9) << where;
      // Single-scattering microfacets lose some energy (most from inside, where TIR adds bounces).
      EXPECT_GT(energy, 0.7) << where;
      EXPECT_NEAR(sampled_r / n, eval_r / n, 0.01) << where;
      // eval lets radiance pass unscaled (Cycles' rule); photon samples carry flux by the same rule,
      // scaled by (eta_o / eta_i)^2 on refraction (shading/lobes.h).
      EXPECT_NEAR(sampled_t / n, eval_t / n * (eta_o / eta_i) * (eta_o / eta_i), 0.03) << where;
    }
  }
}

}  // namespace
}  // namespace ppm
