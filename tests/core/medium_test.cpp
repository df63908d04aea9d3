// The media's numeric pieces outside the free-path samplers (free_path_test.cpp): the 3-D
// progressive radius rule and its volume estimate (progressive.h, pixel_stats.h), a homogeneous
// medium's emission along a segment, what varies in a medium, and the medium stack (scene/medium.h).
#include "ppm/pixel_stats.h"
#include "ppm/progressive.h"
#include "scene/medium.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ppm {
namespace {

// Photons scattered uniformly in a medium with density `density` per m^3 per pass, each of flux
// `flux`: m = density 4/3 pi r^3 a pass. The volume estimate tau / (4/3 pi r^3 passes) must stay
// at density * flux while r shrinks by the 3-D rule; the 2-D rule (r^2 by the ratio) would make
// it drift (checked below), which is what the rule is for.
double drift(bool volume_rule, double alpha, uint32_t threshold) {
  double r2 = 1.0, carry = 0.0;
  HitPointStats s{};
  const double density = 1e5, flux = 1e-3;
  double worst = 0.0;
  for (int pass = 1; pass <= 5000; ++pass) {
    carry += density * 4.0 / 3.0 * kPi * r2 * std::sqrt(r2);
    const double m = std::floor(carry);
    carry -= m;
    s.m += static_cast<uint32_t>(m);
    s.tau_m += Color(m * flux);
    if (volume_rule)
      progressive_update_volume(r2, s, alpha, threshold);
    else
      progressive_update(r2, s, alpha, threshold);
    EXPECT_TRUE(std::isfinite(r2) && r2 > 0.0);
    if (pass % 500 == 0) {
      const Color L = volume_photon_radiance(r2, s, static_cast<double>(pass), 1.0);
      worst = std::fmax(worst, std::fabs(L.x / (density * flux) - 1.0));
    }
  }
  return worst;
}

TEST(VolumeProgressive, TheThreeDimensionalRuleKeepsTheVolumeEstimate) {
  for (double alpha : {0.5, 0.7, 0.9})
    for (uint32_t threshold : {1u, 30u}) EXPECT_LT(drift(true, alpha, threshold), 2e-3) << alpha << " " << threshold;
}

TEST(VolumeProgressive, TheTwoDimensionalRuleWouldNot) {
  EXPECT_GT(drift(false, 0.7, 1), 0.05);
}

TEST(VolumeProgressive, OneUpdateShrinksTheVolumeByTheRatio) {
  double r2 = 4.0;
  HitPointStats s{};
  s.m = 100;
  s.tau_m = Color(2.0);
  const double ratio = progressive_update_volume(r2, s, 0.7, 30);
  EXPECT_DOUBLE_EQ(ratio, 0.7);  // n = 0: (alpha m) / m
  EXPECT_NEAR(r2 * std::sqrt(r2), 8.0 * 0.7, 1e-12);  // r^3 *= ratio
  EXPECT_NEAR(s.tau.x, 1.4, 1e-12);
  EXPECT_EQ(s.m, 0u);
  // Below the threshold nothing moves.
  s.m = 29;
  EXPECT_EQ(progressive_update_volume(r2, s, 0.7, 30), 0.0);
  EXPECT_NEAR(r2 * std::sqrt(r2), 5.6, 1e-12);
}

TEST(VolumeProgressive, FloatPixelStatsFoldLikeTheDoubleRule) {
  FloatPhotonStats f{};
  f.r2 = 1.0f;
  double r2 = 1.0;
  HitPointStats s{};
  for (int pass = 0; pass < 50; ++pass) {
    f.fold_volume(40, Vec3f(0.5f), 0.7, 30);
    s.m += 40;
    s.tau_m += Color(0.5);
    progressive_update_volume(r2, s, 0.7, 30);
  }
  EXPECT_NEAR(f.r2, r2, 1e-5 * r2);
  EXPECT_NEAR(f.tau.x, s.tau.x, 1e-4 * s.tau.x);
}

TEST(MediumEmission, IntegralOfTransmittedEmissionPerChannel) {
  Medium m;
  m.c.emission = Color(1.0, 1.0, 0.0);
  m.sigma_t = Color(1.0, 0.0, 2.0);
  const Color along = medium_emission_along(m, 2.0);
  EXPECT_NEAR(along.x, 1.0 - std::exp(-2.0), 1e-12);
  EXPECT_NEAR(along.y, 2.0, 1e-12);  // no extinction: emission times length
  EXPECT_EQ(along.z, 0.0);           // no emission
  const Color far = medium_emission_along(m, kInf);
  EXPECT_NEAR(far.x, 1.0, 1e-12);  // emission / sigma_t
  EXPECT_EQ(far.y, 0.0);           // no extinction to infinity: left out, never infinite
  EXPECT_EQ(medium_emission_along(m, std::nan("")).x, 0.0);
}

// A field that drives emission alone leaves sigma_t constant: photons and shadow rays then sample
// the medium as a homogeneous one. Any term with extinction, in any of a sum's parts, varies it.
TEST(MediumField, ExtinctionVariesOnlyWhereATermCarriesSome) {
  auto field = [](Color sigma_a, Color sigma_s, Color emission) {
    auto f = std::make_shared<MediumField>();
    f->terms.push_back(MediumTerm{sigma_a, sigma_s, emission, 0});
    return f;
  };
  Medium m;
  EXPECT_FALSE(m.varies() || m.extinction_varies());
  m.uses.push_back(FieldUse{field(Color(0.0), Color(0.0), Color(4.0)), 0});
  EXPECT_TRUE(m.varies());
  EXPECT_FALSE(m.extinction_varies());
  m.uses.push_back(FieldUse{field(Color(0.0), Color(0.0, 0.0, 0.5), Color(0.0)), 1});
  EXPECT_TRUE(m.extinction_varies());
  m.uses.back() = FieldUse{field(Color(0.2, 0.0, 0.0), Color(0.0), Color(0.0)), 1};
  EXPECT_TRUE(m.extinction_varies());
}

TEST(MediumStack, NestsAndLeavesInAnyOrder) {
  MediumStack s;
  EXPECT_EQ(s.top(-1), -1);
  EXPECT_EQ(s.top(5), 5);  // the world's medium where the stack is empty
  s.enter(1);              // fog box
  s.enter(2);              // glass with liquid
  EXPECT_EQ(s.top(0), 2);
  s.leave(1);  // overlapping boxes: leaving the outer one first keeps the inner one
  EXPECT_EQ(s.top(0), 2);
  s.leave(2);
  EXPECT_EQ(s.top(0), 0);
  s.leave(7);  // leaving a medium never entered (an open mesh seen from inside) changes nothing
  EXPECT_EQ(s.count, 0);
}

TEST(MediumStack, AHundredNestedBoxesOverflowWithoutLosingTheOuterOnes) {
  MediumStack s;
  for (int k = 0; k < 100; ++k) s.enter(k);
  EXPECT_EQ(s.count, kMaxMediumStack);
  EXPECT_EQ(s.top(-1), kMaxMediumStack - 1);  // deeper entries are counted, not kept
  for (int k = 99; k >= kMaxMediumStack; --k) s.leave(k);
  EXPECT_EQ(s.overflow, 0);
  EXPECT_EQ(s.top(-1), kMaxMediumStack - 1);
  for (int k = kMaxMediumStack - 1; k >= 0; --k) {
    EXPECT_EQ(s.top(-1), k);
    s.leave(k);
  }
  EXPECT_EQ(s.top(-1), -1);
}

}  // namespace
}  // namespace ppm
