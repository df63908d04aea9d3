// Mixtures of lobes (shading/closure.h): sampling agrees with evaluation, for eye paths and for
// photons (the adjoint); a white mixture of lossless lobes loses nothing, also under a layer;
// layers attenuate what lies below by their tabulated albedo; the eye pass's delta split is whole.
#include "lobe_test_helpers.h"
#include "math/rng.h"
#include "math/sampling.h"
#include "shading/closure.h"
#include "shading/microfacet.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

namespace ppm {
namespace {

Lobe lobe(LobeKind kind, Color weight, Color color, double roughness = 0.0) {
  Lobe l;
  l.kind = kind;
  l.weight = weight;
  l.color = color;
  l.roughness = roughness;
  return l;
}

// The whole BSDF but its delta lobes: what hit points store (closure_eval) and the rough lobes eye
// paths follow (closure_eval_followed_rough).
Color full_eval(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  return closure_eval(lobes, sp, wo, wi) + closure_eval_followed_rough(lobes, sp, wo, wi);
}

Lobe specular_layer(double roughness, double ior = 1.5) {
  Lobe l = lobe(LobeKind::Dielectric, Color(1.0), Color(1.0), roughness);
  l.parts = kReflection;
  l.layer = true;
  l.multiscatter = true;
  l.ior = ior;
  prepare_lobe(l);
  return l;
}

// Mean sampled weight (all directions) against the integral of f cos over the sphere, both red.
// `adjoint`: photons, whose mean weight is the integral of f(wi, wo) cos(wi).
void expect_sampling_matches_eval(const std::vector<Lobe>& lobes, const Vec3& wo, bool adjoint, double tol,
                                  const SurfacePoint& sp = kFlat) {
  Rng rng(5, 6, 7);
  const int n = test_samples(300000);
  double sampled = 0.0, integrated = 0.0;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    if (closure_sample(lobes, sp, wo, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), adjoint, s) &&
        !s.specular)
      sampled += s.weight.x;
    for (int k = 0; k < 8; ++k) {
      const Vec3 wi = sample_uniform_sphere((k + rng.uniform()) / 8.0, rng.uniform());
      const Color f = adjoint ? full_eval(lobes, sp, wi, wo) : full_eval(lobes, sp, wo, wi);
      integrated += f.x * std::fabs(glm::dot(wi, sp.ns)) * 4.0 * kPi / 8.0;
    }
  }
  EXPECT_NEAR(sampled / n, integrated / n, tol) << (adjoint ? "photons" : "eye");
}

TEST(Closure, SamplingMatchesEvaluationForEyePathsAndPhotons) {
  const std::vector<Lobe> lobes = {specular_layer(0.4), lobe(LobeKind::Diffuse, Color(0.5), Color(0.8)),
                                   lobe(LobeKind::Conductor, Color(0.3), Color(0.9, 0.6, 0.3), 0.5),
                                   lobe(LobeKind::Translucent, Color(0.2), Color(0.7))};
  for (double cos_o : {0.95, 0.5, 0.15}) {
    expect_sampling_matches_eval(lobes, direction(cos_o, 0.3), false, 0.01);
    expect_sampling_matches_eval(lobes, direction(cos_o, 0.3), true, 0.01);
  }
}

// Energy sent anywhere by one sample, averaged: delta lobes included.
double mean_albedo(const std::vector<Lobe>& lobes, const Vec3& wo, bool adjoint) {
  Rng rng(11, 12, 13);
  const int n = test_samples(200000);
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    if (closure_sample(lobes, kFlat, wo, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), adjoint, s))
      sum += luminance(s.weight);
  }
  return sum / n;
}

Lobe rough_diffuse(double roughness, Color color, bool multiscatter) {
  Lobe l = lobe(LobeKind::Diffuse, Color(1.0), color, roughness);
  l.multiscatter = multiscatter;
  return l;
}

TEST(Closure, OrenNayarSamplingMatchesEvaluation) {
  for (bool multiscatter : {false, true})
    for (double cos_o : {0.9, 0.3}) {
      const std::vector<Lobe> lobes = {rough_diffuse(0.8, Color(0.7), multiscatter)};
      expect_sampling_matches_eval(lobes, direction(cos_o, 0.3), false, 0.01);
      expect_sampling_matches_eval(lobes, direction(cos_o, 0.3), true, 0.01);
    }
}

TEST(Closure, WhiteOrenNayarLosesOnlyWithoutItsEnergyCompensation) {
  // Fujii's model alone loses light as roughness grows (Blender 3.x to 4.2); Blender 4.3's
  // multiple-scattering term gives it back. A smooth one is Lambert's.
  for (double cos_o : {0.9, 0.5, 0.15}) {
    const Vec3 wo = direction(cos_o);
    EXPECT_NEAR(mean_albedo({rough_diffuse(1e-9, Color(1.0), false)}, wo, false), 1.0, 0.005);
    const double single = mean_albedo({rough_diffuse(1.0, Color(1.0), false)}, wo, false);
    EXPECT_LT(single, 0.97) << cos_o;
    EXPECT_GT(single, 0.75) << cos_o;
    EXPECT_NEAR(mean_albedo({rough_diffuse(1.0, Color(1.0), true)}, wo, false), 1.0, 0.02) << cos_o;
    const double grey = mean_albedo({rough_diffuse(1.0, Color(0.5), true)}, wo, false);
    EXPECT_GT(grey, 0.5 * single);
    EXPECT_LT(grey, 0.5);
  }
}

// A normal map's point: the shading normal tilted by `degrees` towards +x from the smooth +z.
SurfacePoint mapped_point(double degrees, BumpSoftening softening) {
  SurfacePoint sp = kFlat;
  sp.smooth_normal = Vec3(0, 0, 1);
  sp.ns = Vec3(std::sin(degrees * kPi / 180.0), 0.0, std::cos(degrees * kPi / 180.0));
  sp.softening = softening;
  return sp;
}

TEST(Closure, BumpShadowingSoftensDiffuseLightTowardsTheSmoothTerminator) {
  const std::vector<Lobe> diffuse = {lobe(LobeKind::Diffuse, Color(1.0), Color(0.8))};
  const Vec3 wo = direction(0.8, 0.5);
  for (BumpSoftening softening : {BumpSoftening::Chiang, BumpSoftening::ContyEstevez}) {
    const SurfacePoint sp = mapped_point(30.0, softening), plain = mapped_point(30.0, BumpSoftening::None);
    // Light along the smooth normal: nothing lost. Light near the smooth horizon, on the side the
    // normal tilts to: less, and less the closer it gets.
    const Vec3 up(0, 0, 1);
    EXPECT_NEAR(full_eval(diffuse, sp, wo, up).x, full_eval(diffuse, plain, wo, up).x, 1e-12);
    const double grazing = full_eval(diffuse, sp, wo, direction(0.1, 0.0)).x;
    const double lower = full_eval(diffuse, sp, wo, direction(0.05, 0.0)).x;
    EXPECT_LT(grazing, full_eval(diffuse, plain, wo, direction(0.1, 0.0)).x);
    EXPECT_LT(lower, grazing);
    EXPECT_GT(lower, 0.0);
    // Eye paths only: photons scatter within the tilted normal's hemisphere, while f also lets a
    // viewer below it (above the surface) see light; the gather evaluates f, so only light that
    // photons carry on from such a surface is short by that sliver.
    for (double cos_o : {0.9, 0.4}) expect_sampling_matches_eval(diffuse, direction(cos_o, 0.3), false, 0.01, sp);
  }
  // The newer form refuses light from below the smooth horizon even where the tilted normal takes
  // it, for glossy lobes too.
  const SurfacePoint sp = mapped_point(30.0, BumpSoftening::ContyEstevez);
  const Vec3 below(std::sin(100.0 * kPi / 180.0), 0.0, std::cos(100.0 * kPi / 180.0));
  ASSERT_GT(glm::dot(below, sp.ns), 0.0);
  EXPECT_EQ(full_eval(diffuse, sp, wo, below).x, 0.0);
  const std::vector<Lobe> glossy = {lobe(LobeKind::Glossy, Color(1.0), Color(0.8), 0.6)};
  const Vec3 mirror = 2.0 * glm::dot(below, sp.ns) * sp.ns - below;  // where the tilted normal reflects it
  ASSERT_GT(mirror.z, 0.0);
  EXPECT_GT(full_eval(glossy, mapped_point(30.0, BumpSoftening::None), mirror, below).x, 0.0);
  EXPECT_EQ(full_eval(glossy, sp, mirror, below).x, 0.0);
}

TEST(Closure, AnisotropicGlossyStretchesAlongItsTangentAndSamplesAsItEvaluates) {
  SurfacePoint sp = kFlat;
  sp.tangent = Vec3(1, 0, 0.3);  // not in the surface: projected onto it
  Lobe brushed = lobe(LobeKind::Conductor, Color(1.0), Color(0.9, 0.7, 0.5), 0.4);
  brushed.stretch_x = 1.0 / std::sqrt(0.1);  // Principled, Anisotropic 1: aspect sqrt(1 - 0.9)
  brushed.stretch_y = std::sqrt(0.1);
  const Vec3 wo = direction(0.7, 0.0);
  const Vec3 mirror(-wo.x, -wo.y, wo.z);
  // Off the mirror direction by the same angle along the tangent (x) and across it (y).
  const Vec3 along = glm::normalize(mirror + Vec3(0.2, 0.0, 0.0)), across = glm::normalize(mirror + Vec3(0.0, 0.2, 0.0));
  EXPECT_GT(full_eval({brushed}, sp, wo, along).x, 3.0 * full_eval({brushed}, sp, wo, across).x);
  brushed.rotation = 0.25;  // a quarter turn: the tangent along y
  EXPECT_LT(full_eval({brushed}, sp, wo, along).x, full_eval({brushed}, sp, wo, across).x / 3.0);
  for (double cos_o : {0.9, 0.4}) {
    expect_sampling_matches_eval({brushed}, direction(cos_o, 0.3), false, 0.01, sp);
    expect_sampling_matches_eval({brushed}, direction(cos_o, 0.3), true, 0.01, sp);
  }
  Rng rng(3, 3, 3);
  for (int i = 0; i < 50; ++i) {
    const Vec3 a = direction(0.05 + 0.95 * rng.uniform(), 6.28 * rng.uniform());
    const Vec3 b = direction(0.05 + 0.95 * rng.uniform(), 6.28 * rng.uniform());
    EXPECT_NEAR(full_eval({brushed}, sp, a, b).x, full_eval({brushed}, sp, b, a).x, 1e-9);
  }
  // Without a tangent (not a mesh with one) it stays isotropic.
  Lobe round = lobe(LobeKind::Conductor, Color(1.0), Color(0.9, 0.7, 0.5), 0.4);
  EXPECT_NEAR(full_eval({brushed}, kFlat, wo, along).x, full_eval({round}, kFlat, wo, along).x, 1e-12);
}

TEST(Closure, SheenLobesSampleAsTheyEvaluateAreReciprocalAndCreateNoEnergy) {
  for (LobeKind kind : {LobeKind::Velvet, LobeKind::SchlickSheen})
    for (double sigma : {0.2, 1.0}) {
      const std::vector<Lobe> sheen = {lobe(kind, Color(1.0), Color(1.0), sigma)};
      for (double cos_o : {0.95, 0.5, 0.1}) {
        expect_sampling_matches_eval(sheen, direction(cos_o, 0.3), false, 0.01);
        expect_sampling_matches_eval(sheen, direction(cos_o, 0.3), true, 0.01);
        EXPECT_LT(mean_albedo(sheen, direction(cos_o), false), 1.0);
      }
      Rng rng(4, 4, 4);
      for (int i = 0; i < 50; ++i) {
        const Vec3 a = direction(0.05 + 0.95 * rng.uniform(), 6.28 * rng.uniform());
        const Vec3 b = direction(0.05 + 0.95 * rng.uniform(), 6.28 * rng.uniform());
        EXPECT_NEAR(full_eval(sheen, kFlat, a, b).x, full_eval(sheen, kFlat, b, a).x, 1e-9);
      }
    }
  // Velvet sends light back towards grazing light (its D peaks at theta_h = 90 degrees).
  const std::vector<Lobe> velvet = {lobe(LobeKind::Velvet, Color(1.0), Color(1.0), 0.5)};
  const Vec3 grazing = direction(0.2, 0.0), steep = direction(0.9, 0.0);
  EXPECT_GT(full_eval(velvet, kFlat, grazing, grazing).x, 10.0 * full_eval(velvet, kFlat, steep, steep).x);
}

TEST(Closure, WhiteLosslessMixturesLoseNothing) {
  Lobe glass = lobe(LobeKind::Dielectric, Color(0.3), Color(1.0));
  glass.tint = Color(1.0);
  const std::vector<Lobe> mix = {lobe(LobeKind::Diffuse, Color(0.4), Color(1.0)), glass,
                                 lobe(LobeKind::Transparent, Color(0.2), Color(1.0)),
                                 lobe(LobeKind::Conductor, Color(0.1), Color(1.0))};
  for (double cos_o : {0.9, 0.4, 0.1}) EXPECT_NEAR(mean_albedo(mix, direction(cos_o), false), 1.0, 0.005);
}

TEST(Closure, WhiteDiffuseUnderALayerLosesNothing) {
  // What the layer reflects plus what it lets through to a white diffuse base is all the light.
  for (double roughness : {0.0, 0.3, 0.7}) {
    const std::vector<Lobe> lobes = {specular_layer(roughness), lobe(LobeKind::Diffuse, Color(1.0), Color(1.0))};
    for (double cos_o : {0.9, 0.5, 0.2})
      EXPECT_NEAR(mean_albedo(lobes, direction(cos_o), false), 1.0, 0.005)
          << roughness << " " << cos_o;
  }
}

TEST(Closure, MultiscatterRestoresWhatSingleScatteringLoses) {
  // A white glossy lobe keeps all the light at any roughness (single scattering alone loses up to
  // a third at roughness 1); a coloured one keeps less than white, and more than single scattering.
  for (double roughness : {0.2, 0.5, 0.8, 1.0}) {
    for (double cos_o : {0.9, 0.4}) {
      Lobe white = lobe(LobeKind::Glossy, Color(1.0), Color(1.0), roughness);
      const double single = mean_albedo({white}, direction(cos_o), false);
      white.multiscatter = true;
      EXPECT_NEAR(mean_albedo({white}, direction(cos_o), false), 1.0, 0.01) << roughness << " " << cos_o;
      EXPECT_LT(single, roughness >= 0.5 ? 0.97 : 1.0);
      Lobe gold = lobe(LobeKind::Conductor, Color(1.0), Color(1.0, 0.76, 0.33), roughness);
      const double gold_single = mean_albedo({gold}, direction(cos_o), false);
      gold.multiscatter = true;
      const double gold_multi = mean_albedo({gold}, direction(cos_o), false);
      EXPECT_GT(gold_multi, gold_single);
      EXPECT_LT(gold_multi, 1.0);
    }
  }
}

TEST(Closure, BeckmannLobesSampleAsTheyEvaluateAndItsDistributionIsNormalised) {
  for (double a : {0.1, 0.4, 0.9}) {  // the projected area of the normals is the surface's
    Rng rng(8, 8, 8);
    double sum = 0.0;
    const int n = test_samples(400000);
    for (int i = 0; i < n; ++i) {
      const Vec3 h = sample_uniform_hemisphere(rng.uniform(), rng.uniform());
      sum += beckmann_d(h, a, a * 0.5) * h.z * 2.0 * kPi;
    }
    EXPECT_NEAR(sum / n, 1.0, a < 0.2 ? 0.05 : 0.01) << a;
  }
  Lobe metal = lobe(LobeKind::Conductor, Color(1.0), Color(0.9, 0.6, 0.3), 0.5);
  metal.beckmann = true;
  for (double cos_o : {0.9, 0.4}) {
    expect_sampling_matches_eval({metal}, direction(cos_o, 0.3), false, 0.01);
    expect_sampling_matches_eval({metal}, direction(cos_o, 0.3), true, 0.01);
  }
  // Glass (followed by eye paths, so not in closure_eval): its own sampling against its evaluation.
  const DielectricParams glass{1.5, 0.5, Color(1.0), Color(1.0), kReflectionAndRefraction, false, true};
  for (double cos_o : {0.9, 0.4, -0.6}) {
    const Vec3 wo = direction(cos_o, 0.3);
    Rng rng(5, 6, 7);
    const int n = test_samples(200000);
    double sampled = 0.0, integrated = 0.0;
    for (int i = 0; i < n; ++i) {
      BsdfSample s;
      if (dielectric_sample(glass, kFlat, wo, rng.uniform(), rng.uniform(), rng.uniform(), false, s))
        sampled += s.weight.x;
      for (int k = 0; k < 32; ++k) {
        const Vec3 wi = sample_uniform_sphere((k + rng.uniform()) / 32.0, rng.uniform());
        integrated += dielectric_eval(glass, kFlat, wo, wi).x * std::fabs(wi.z) * 4.0 * kPi / 32.0;
      }
    }
    EXPECT_NEAR(sampled / n, integrated / n, 0.01) << cos_o;
  }
  // Beckmann's highlight is narrower in its tails than GGX's at the same roughness.
  Lobe ggx = metal;
  ggx.beckmann = false;
  const Vec3 wo = direction(0.8), mirror(-wo.x, -wo.y, wo.z), tail = glm::normalize(mirror + Vec3(0.0, 0.9, 0.0));
  EXPECT_LT(full_eval({metal}, kFlat, wo, tail).x, 0.7 * full_eval({ggx}, kFlat, wo, tail).x);
}

TEST(Closure, MultiscatterGlassLosesNothingFromEitherSide) {
  // Reflection plus refraction of white rough glass keep all the light with Multiscatter GGX
  // (single scattering alone loses up to half, from inside), seen from outside and from inside; a tinted
  // Glass BSDF keeps less than white and more than single scattering.
  for (double roughness : {0.3, 0.6, 1.0}) {
    for (double cos_o : {0.9, 0.4, -0.9, -0.4}) {
      Lobe glass = lobe(LobeKind::Dielectric, Color(1.0), Color(1.0), roughness);
      glass.ior = 1.45;
      prepare_lobe(glass);
      const double single = mean_albedo({glass}, direction(cos_o), false);
      glass.multiscatter = true;
      prepare_lobe(glass);
      EXPECT_NEAR(mean_albedo({glass}, direction(cos_o), false), 1.0, 0.01) << roughness << " " << cos_o;
      EXPECT_LT(single, roughness >= 0.6 ? 0.98 : 0.9995) << roughness << " " << cos_o;
      Lobe tinted = glass;
      tinted.color = tinted.tint = Color(0.7);
      const double tinted_multi = mean_albedo({tinted}, direction(cos_o), false);
      tinted.multiscatter = false;
      EXPECT_GT(tinted_multi, mean_albedo({tinted}, direction(cos_o), false));
      EXPECT_LT(tinted_multi, 0.7 + 1e-3);
    }
  }
}

TEST(Closure, ASmoothLayerAttenuatesWhatLiesBelowByItsFresnel) {
  const std::vector<Lobe> lobes = {specular_layer(0.0), lobe(LobeKind::Diffuse, Color(1.0), Color(0.5))};
  for (double cos_o : {1.0, 0.5, 0.1}) {
    const Vec3 wo = direction(cos_o), wi = direction(0.7, 2.0);
    const double F = fresnel_dielectric(cos_o, 1.0, 1.5);
    EXPECT_NEAR(full_eval(lobes, kFlat, wo, wi).x, (1.0 - F) * 0.5 / kPi, 2e-3 * 0.5 / kPi) << cos_o;
  }
}

// Hit points gather as diffuse ones where closure_lambertian says so: the evaluated lobes must then
// give albedo / pi for every wi on the viewer's side, and it must refuse what varies with wi.
TEST(Closure, LambertianWhereEveryEvaluatedLobeIsSmoothDiffuse) {
  const std::vector<Lobe> coat_and_mirror = {specular_layer(0.0), lobe(LobeKind::Diffuse, Color(0.6), Color(0.5)),
                                             lobe(LobeKind::Conductor, Color(0.4), Color(0.9), 0.0)};
  Rng rng(3, 4, 5);
  for (double cos_o : {1.0, 0.5, 0.1}) {
    const Vec3 wo = direction(cos_o, 0.4);
    Color albedo;
    ASSERT_TRUE(closure_lambertian(coat_and_mirror, kFlat, wo, albedo)) << cos_o;
    EXPECT_GT(albedo.x, 0.0);
    for (int i = 0; i < 20; ++i) {
      const Vec3 wi = direction(0.02 + 0.98 * rng.uniform(), 6.28 * rng.uniform());
      EXPECT_NEAR(full_eval(coat_and_mirror, kFlat, wo, wi).x, albedo.x / kPi, 1e-12) << cos_o;
    }
  }
  Color albedo;
  const Lobe diffuse = lobe(LobeKind::Diffuse, Color(0.5), Color(0.8));
  EXPECT_FALSE(closure_lambertian({diffuse, rough_diffuse(0.5, Color(0.8), true)}, kFlat, direction(0.7), albedo));
  // A rough metal beside it is followed by eye paths, not evaluated: the rest is Lambertian.
  ASSERT_TRUE(closure_lambertian({diffuse, lobe(LobeKind::Conductor, Color(0.5), Color(0.9), 0.4)}, kFlat,
                                 direction(0.7), albedo));
  EXPECT_NEAR(albedo.x, 0.4, 1e-12);
  EXPECT_FALSE(closure_lambertian({diffuse, lobe(LobeKind::Translucent, Color(0.5), Color(0.8))}, kFlat,
                                  direction(0.7), albedo));
  EXPECT_FALSE(closure_lambertian({diffuse}, mapped_point(30.0, BumpSoftening::Chiang), direction(0.7), albedo));
}

TEST(Closure, WithoutLayersItIsReciprocal) {
  const std::vector<Lobe> lobes = {lobe(LobeKind::Diffuse, Color(0.3), Color(0.8)),
                                   lobe(LobeKind::Conductor, Color(0.4), Color(0.9), 0.4),
                                   rough_diffuse(0.7, Color(0.6), true)};
  Rng rng(2, 2, 2);
  for (int i = 0; i < 100; ++i) {
    const Vec3 a = direction(0.05 + 0.95 * rng.uniform(), 6.28 * rng.uniform());
    const Vec3 b = direction(0.05 + 0.95 * rng.uniform(), 6.28 * rng.uniform());
    const Color fab = full_eval(lobes, kFlat, a, b), fba = full_eval(lobes, kFlat, b, a);
    EXPECT_NEAR(fab.x, fba.x, 1e-9 * (1.0 + fab.x));
  }
}

TEST(Closure, DeltaShareAndBranchesSplitTheSurfaceWhole) {
  // Half smooth mirror, half diffuse (both white): the eye pass follows the mirror with
  // probability `share` and divides by it, so the expected mirror weight is its own, 0.5.
  const std::vector<Lobe> lobes = {lobe(LobeKind::Conductor, Color(0.5), Color(1.0)),
                                   lobe(LobeKind::Diffuse, Color(0.5), Color(1.0))};
  const Vec3 wo = direction(0.8);
  const double share = closure_followed_share(lobes, kFlat, wo);
  EXPECT_NEAR(share, 0.5, 1e-9);
  BsdfSample b[2];
  ASSERT_EQ(closure_followed_branches(lobes, kFlat, wo, 0.3, 0.5, 0.5, 0.5, b), 1);
  EXPECT_TRUE(b[0].specular);
  EXPECT_NEAR(b[0].weight.x, 0.5, 1e-9);  // its weight 0.5, Fresnel 1, the only delta lobe (picked always)
  EXPECT_NEAR(b[0].wi.z, wo.z, 1e-12);
  EXPECT_TRUE(closure_has_followed(lobes));
  EXPECT_FALSE(closure_is_followed(lobes));
  // A transparent lobe keeps the ray's kind and direction.
  const std::vector<Lobe> clear = {lobe(LobeKind::Transparent, Color(1.0), Color(0.5, 1.0, 1.0))};
  ASSERT_EQ(closure_followed_branches(clear, kFlat, wo, 0.9, 0.5, 0.5, 0.5, b), 1);
  EXPECT_EQ(b[0].ray_kind, 0);
  EXPECT_NEAR(glm::dot(b[0].wi, -wo), 1.0, 1e-12);
  EXPECT_NEAR(b[0].weight.x, 0.5, 1e-12);
}

TEST(Closure, FollowedDensityIsWhatTheDrawsOfRoughFollowedLobesHave) {
  // Each rough followed lobe beside a smooth mirror (a delta lobe, which has no density): for every
  // direction drawn from the rough one, f cos / pdf of the followed rough lobes is the draw's weight,
  // the share of the pick included. GGX (anisotropic too) and Beckmann, glass from both sides.
  Lobe aniso = lobe(LobeKind::Glossy, Color(0.5), Color(0.8), 0.2);
  aniso.stretch_x = 1.6;
  aniso.stretch_y = 0.6;
  Lobe beckmann = lobe(LobeKind::Conductor, Color(0.5), Color(0.9, 0.6, 0.3), 0.15);
  beckmann.beckmann = true;
  Lobe glass = lobe(LobeKind::Dielectric, Color(0.5), Color(1.0), 0.35);
  glass.ior = 1.5;
  SurfacePoint sp = kFlat;
  sp.tangent = Vec3(1.0, 0.0, 0.0);
  const Lobe mirror = lobe(LobeKind::Conductor, Color(0.5), Color(1.0));
  Rng rng(3, 4, 5);
  for (const Lobe& rough : {aniso, beckmann, glass}) {
    const std::vector<Lobe> lobes = {mirror, rough};
    for (double cos_o : {0.9, 0.4, -0.6}) {
      if (cos_o < 0.0 && rough.kind != LobeKind::Dielectric) continue;
      const Vec3 wo = direction(cos_o, 0.7);
      int drawn = 0;
      for (int i = 0; i < 2000; ++i) {
        BsdfSample b[2];
        if (closure_followed_branches(lobes, sp, wo, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), b) != 1 ||
            b[0].specular)
          continue;
        ++drawn;
        const double pdf = closure_followed_pdf(lobes, sp, wo, b[0].wi);
        ASSERT_GT(pdf, 0.0);
        const Color f = closure_eval_followed_rough(lobes, sp, wo, b[0].wi);
        const Color weight = f * (std::fabs(b[0].wi.z) / pdf);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(weight[c], b[0].weight[c], 1e-6 * (1.0 + b[0].weight[c]));
      }
      EXPECT_GT(drawn, 500);
    }
  }
  // The delta lobe alone has no density, nor a rough lobe's draw away from its side.
  const std::vector<Lobe> smooth = {mirror};
  EXPECT_EQ(closure_followed_pdf(smooth, kFlat, direction(0.8), direction(0.8, kPi)), 0.0);
  EXPECT_FALSE(closure_has_rough_followed(smooth, kFlat));
  EXPECT_EQ(closure_followed_pdf({mirror, beckmann}, kFlat, direction(0.8), direction(-0.5)), 0.0);
}

}  // namespace
}  // namespace ppm
