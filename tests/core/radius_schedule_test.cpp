// The global radius schedule (ppm/radius_schedule.h) against its defining product.
#include "ppm/radius_schedule.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ppm {
namespace {

TEST(GlobalRadiusSchedule, IsKnausZwickersProduct) {
  for (double alpha : {0.1, 0.5, 0.7, 0.95}) {
    double product = 1.0;  // r_j^2 / r_1^2 = prod_{i=1}^{j-1} (i + alpha) / (i + 1)
    for (uint64_t j = 1; j <= 5000; ++j) {
      // lgamma's of ~4e4 differ: their rounding leaves ~1e-11 of the factor (radius_schedule.h)
      EXPECT_NEAR(global_radius_factor(j, alpha), product, 1e-10 * product) << "alpha " << alpha << " pass " << j;
      product *= (static_cast<double>(j) + alpha) / (static_cast<double>(j) + 1.0);
    }
  }
}

TEST(GlobalRadiusSchedule, ShrinksAsAPowerOfThePass) {
  // Gamma(j + alpha) / Gamma(j + 1) = j^(alpha - 1) (1 + alpha (alpha - 1) / (2 j) + O(1 / j^2)).
  const double alpha = 0.7, j = 1e6;
  EXPECT_NEAR(global_radius_factor(1000000, alpha) * std::tgamma(1.0 + alpha) / std::pow(j, alpha - 1.0),
              1.0 + alpha * (alpha - 1.0) / (2.0 * j), 1e-8);
  EXPECT_GT(global_radius_factor(1ull << 40, alpha), 0.0);  // the last pass a share may start at: not 0
  EXPECT_EQ(global_radius_factor(0, alpha), 1.0);
  EXPECT_EQ(global_radius_factor(1, alpha), 1.0);
}

TEST(GlobalRadiusSchedule, InAMediumTheSphereVolumeFollowsTheProduct) {
  // A hit point in a medium: r_j^3 / r_1^3 is the product, so r_j^2 / r_1^2 its 2/3 power.
  const double alpha = 0.7;
  double product = 1.0;
  for (uint64_t j = 1; j <= 2000; ++j) {
    EXPECT_NEAR(std::pow(global_radius_factor_in(3, j, alpha), 1.5), product, 1e-10 * product) << "pass " << j;
    EXPECT_EQ(global_radius_factor_in(2, j, alpha), global_radius_factor(j, alpha));
    product *= (static_cast<double>(j) + alpha) / (static_cast<double>(j) + 1.0);
  }
  EXPECT_GT(global_radius_factor_in(3, 1000, alpha), global_radius_factor(1000, alpha));  // shrinks slower
}

}  // namespace
}  // namespace ppm
