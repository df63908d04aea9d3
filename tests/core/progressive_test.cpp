// The progressive radius/flux update under stress: 10,000 updates, radii
// driven towards underflow, flux sums growing. Nothing may become NaN, Inf,
// zero or denormal, and the estimate tau / (pi r^2 N) must stay consistent.
#include "ppm/pixel_stats.h"
#include "ppm/progressive.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

namespace ppm {
namespace {

bool normal_or_zero(double x) { return x == 0.0 || std::fpclassify(x) == FP_NORMAL; }

// Photons landing uniformly with density `density` per m^2 per pass, each of
// flux `flux`: m = density pi r^2 per pass, tau_m = m flux. The estimate
// tau / (pi r^2 passes) must stay at density * flux while r shrinks (the
// shrink assumes a uniform density, which this is).
TEST(Progressive, TenThousandPassesKeepTheEstimate) {
  for (double alpha : {0.5, 0.7, 0.9}) {
    for (uint32_t threshold : {1u, 10u}) {
      double r2 = 1.0;
      HitPointStats s{};
      const double density = 1e6, flux = 1e-3;
      double carry = 0.0;
      for (int pass = 1; pass <= 10000; ++pass) {
        carry += density * kPi * r2;  // expected photons this pass; whole photons only
        const double m = std::floor(carry);
        carry -= m;
        s.m += static_cast<uint32_t>(m);
        s.tau_m += Color(m * flux);
        progressive_update(r2, s, alpha, threshold);
        ASSERT_TRUE(std::isfinite(r2) && r2 > 0.0 && normal_or_zero(r2));
        ASSERT_TRUE(std::isfinite(s.n) && std::isfinite(s.tau.x));
        if (pass % 1000 == 0) {
          const Color L = photon_radiance(r2, s, static_cast<double>(pass), 1.0);
          EXPECT_NEAR(L.x, density * flux, 1e-3 * density * flux) << alpha << " " << pass;
        }
      }
      EXPECT_LT(r2, 0.5);  // it did shrink (to 0.006, 0.05, 0.37 for alpha 0.5, 0.7, 0.9)
    }
  }
}

// Each update with m >> n shrinks r^2 by about alpha: 10,000 of them with
// alpha = 0.01 would take r^2 to 1e-20000. The floor stops the shrinking at
// kMinRadius2; from then on every photon counts at the fixed radius.
TEST(Progressive, RadiusStopsAtTheFloorInsteadOfUnderflowing) {
  double r2 = 1.0;
  HitPointStats s{};
  const double flux = 1e20;  // flux sums grow too
  for (int pass = 1; pass <= 10000; ++pass) {
    const uint32_t m = 4000000000u;  // near the uint32 limit, every pass
    const double before_r2 = r2;
    const Color before = photon_radiance(r2, s, pass - 1.0, 1.0) * (pass - 1.0);  // tau / (pi r^2)
    s.m += m;
    s.tau_m += Color(flux * r2);  // photons gathered in proportion to the area
    progressive_update(r2, s, 0.01, 1);
    ASSERT_GE(r2, kMinRadius2);
    ASSERT_LE(r2, before_r2);
    ASSERT_EQ(s.m, 0u);
    ASSERT_TRUE(normal_or_zero(r2) && normal_or_zero(s.tau.x) && std::isfinite(s.n));
    const Color after = photon_radiance(r2, s, pass, 1.0) * static_cast<double>(pass);
    ASSERT_TRUE(std::isfinite(after.x) && after.x > 0.0);
    // Each pass adds flux * r2 / (pi r^2) = flux / pi to the estimate's numerator, up to the shrink.
    if (pass > 1) ASSERT_LE(after.x, before.x + flux / kPi * 1.000001);
  }
  EXPECT_GE(r2, kMinRadius2);
  EXPECT_LT(r2, 1e3 * kMinRadius2);  // it got there
}

TEST(Progressive, NothingHappensBelowTheThreshold) {
  double r2 = 2.0;
  HitPointStats s{};
  s.m = 9;
  s.tau_m = Color(1.0);
  progressive_update(r2, s, 0.7, 10);
  EXPECT_EQ(r2, 2.0);
  EXPECT_EQ(s.m, 9u);
  EXPECT_EQ(photon_radiance(0.0, s, 1.0, 1.0).x, 0.0);  // no radius, no estimate: not a division by zero
  EXPECT_EQ(photon_radiance(1.0, s, 0.0, 1.0).x, 0.0);
}

// A pixel's float statistics (pixel_stats.h) over 100,000 passes: the same uniform density as
// above, one pixel, and light that varies by pass. The float running mean stays within 1e-5 of the
// double mean, and the photon estimate within 1e-3 of the density as in double.
TEST(Progressive, FloatPixelStatsKeepTheEstimateOverAHundredThousandPasses) {
  PixelStats px{};
  px.r2 = 1e-2f;
  const double density = 1e6, flux = 1e-3;
  double carry = 0.0, light_sum = 0.0;
  for (uint64_t pass = 1; pass <= 100000; ++pass) {
    carry += density * kPi * px.r2;
    const double m = std::floor(carry);
    carry -= m;
    const float light = 1.0f + 0.5f * static_cast<float>(std::sin(0.37 * static_cast<double>(pass)));
    light_sum += light;
    fold_pass(px, PixelPass{static_cast<uint32_t>(m), Vec3f(static_cast<float>(m * flux)), Vec3f(light), 0.25f}, pass,
              0.7, 30);
    ASSERT_TRUE(px.r2 > 0.0f && std::isfinite(px.tau.x) && std::isfinite(px.n));
  }
  EXPECT_NEAR(px.light.x, light_sum / 100000, 1e-5);
  EXPECT_FLOAT_EQ(px.transparency, 0.25f);
  const HitPointStats s = px.in_double();
  EXPECT_NEAR(photon_radiance(px.r2, s, 100000.0, 1.0).x, density * flux, 1e-3 * density * flux);
}

}  // namespace
}  // namespace ppm
