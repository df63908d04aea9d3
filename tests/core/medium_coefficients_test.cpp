// Volume shader nodes to medium coefficients (shading/medium_coefficients.h), each against the
// arithmetic of Cycles' SVM node written out again here; bad inputs give finite coefficients >= 0.
#include "shading/medium_coefficients.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ppm {
namespace {

void expect_color(const Color& got, const Color& want, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-12 * (1.0 + std::fabs(want[c]))) << what << " " << c;
}

TEST(MediumCoefficients, VolumeScatterScattersOnly) {
  const MediumCoefficients m = volume_scatter(Color(0.8, 0.5, 0.1), 2.0, henyey_greenstein_phase(0.4), 0.5);
  expect_color(m.sigma_s, Color(0.8, 0.5, 0.1), "sigma_s = color density weight");
  expect_color(m.sigma_a, Color(0.0), "sigma_a");
  expect_color(m.sigma_t(), m.sigma_s, "sigma_t");
  EXPECT_DOUBLE_EQ(m.phase.first.g, 0.4);
}

TEST(MediumCoefficients, VolumeAbsorptionAbsorbsOneMinusColor) {
  const MediumCoefficients m = volume_absorption(Color(0.8, 0.5, 0.0), 3.0);
  expect_color(m.sigma_a, Color(0.6, 1.5, 3.0), "sigma_a = (1 - color) density");
  expect_color(m.sigma_s, Color(0.0), "sigma_s");
  // A colour above 1 would be a negative coefficient in Cycles: 0 here.
  expect_color(volume_absorption(Color(2.0, 1.0, 0.5), 1.0).sigma_a, Color(0.0, 0.0, 0.5), "colour above 1");
}

TEST(MediumCoefficients, PrincipledVolumeAsCycles) {
  PrincipledVolumeInputs in;  // Blender's defaults: grey 0.5, density 1, black absorption colour
  MediumCoefficients m = principled_volume(in, Color(1.0));
  expect_color(m.sigma_s, Color(0.5), "default sigma_s");
  expect_color(m.sigma_a, Color(0.5), "default sigma_a");  // (1 - 0.5) (1 - sqrt(0))
  expect_color(m.emission, Color(0.0), "default emission");

  in.color = Color(0.9, 0.3, 1.2);
  in.density = 4.0;
  in.anisotropy = -0.3;
  in.absorption_color = Color(0.25, 1.0, 0.0);
  in.emission_strength = 2.0;
  in.emission_color = Color(1.0, 0.5, 0.25);
  m = principled_volume(in, Color(1.0), 0.5);
  const double density = 0.5 * 4.0;
  const Color absorption(std::max(1.0 - 0.9, 0.0) * std::max(1.0 - std::sqrt(0.25), 0.0),
                         std::max(1.0 - 0.3, 0.0) * std::max(1.0 - std::sqrt(1.0), 0.0),
                         std::max(1.0 - 1.2, 0.0) * std::max(1.0 - std::sqrt(0.0), 0.0));
  expect_color(m.sigma_s, in.color * density, "sigma_s = color density");
  expect_color(m.sigma_a, absorption * density, "sigma_a");
  // Emission is not scaled by density, only by the weight.
  expect_color(m.emission, 2.0 * Color(1.0, 0.5, 0.25) * 0.5, "emission");
  EXPECT_DOUBLE_EQ(m.phase.first.g, -0.3);
  in.density = 0.0;
  expect_color(principled_volume(in, Color(1.0), 0.5).emission, 2.0 * Color(1.0, 0.5, 0.25) * 0.5, "no density");
}

TEST(MediumCoefficients, PrincipledVolumeBlackbodyIsStefanBoltzmann) {
  PrincipledVolumeInputs in;
  in.density = 0.0;
  in.blackbody_intensity = 0.7;
  in.temperature = 1500.0;
  in.blackbody_tint = Color(1.0, 0.8, 0.6);
  const Color bb(1.0, 0.35, 0.05);  // the Blackbody node's colour at 1500 K, as the caller gives it
  const double sigma = 5.670373e-8 * 1e-6 / kPi;
  const double intensity = sigma * ((1.0 - 0.7) * 1.0 + 0.7 * std::pow(1500.0, 4.0));
  EXPECT_NEAR(principled_volume_blackbody_intensity(1500.0, 0.7) / intensity, 1.0, 1e-12);
  expect_color(principled_volume(in, bb, 2.0).emission, in.blackbody_tint * intensity * bb * 2.0, "blackbody");
  in.blackbody_intensity = 0.0;  // off: no term at all, even the mix's constant
  expect_color(principled_volume(in, bb).emission, Color(0.0), "blackbody off");
}

TEST(MediumCoefficients, VolumeCoefficientsAndEmissionAreDirect) {
  const MediumCoefficients m =
      volume_coefficients(Color(1.0, 2.0, 3.0), Color(0.5), Color(0.1, 0.0, 4.0), rayleigh_phase(), 2.0);
  expect_color(m.sigma_a, Color(2.0, 4.0, 6.0), "absorption");
  expect_color(m.sigma_s, Color(1.0), "scatter");
  expect_color(m.emission, Color(0.2, 0.0, 8.0), "emission");
  EXPECT_EQ(m.phase.first.kind, PhaseKind::Rayleigh);
  expect_color(volume_emission(Color(1.0, 0.5, 0.0), 3.0).emission, Color(3.0, 1.5, 0.0), "Emission");
}

TEST(MediumCoefficients, BadInputsGiveFiniteNonNegativeCoefficients) {
  const double nan = std::nan("");
  const auto check = [](const MediumCoefficients& m) {
    for (const Color& c : {m.sigma_a, m.sigma_s, m.emission})
      for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(c[i]) && c[i] >= 0.0);
  };
  for (const double x : {nan, kInf, -kInf, -2.0, 1e308}) {
    check(volume_absorption(Color(x), x, x));
    check(volume_scatter(Color(x, 0.5, -x), x, henyey_greenstein_phase(x), x));
    check(volume_emission(Color(x), x, x));
    check(volume_coefficients(Color(x), Color(-x), Color(x, 1.0, -1.0), rayleigh_phase(), x));
    PrincipledVolumeInputs in;
    in.color = Color(x, 0.2, -x);
    in.density = x;
    in.absorption_color = Color(-1.0, x, 0.5);
    in.emission_strength = x;
    in.blackbody_intensity = x;
    in.temperature = x;
    check(principled_volume(in, Color(x, 1.0, 0.0), x));
    check(principled_volume(in, Color(1.0)));
  }
}

}  // namespace
}  // namespace ppm
