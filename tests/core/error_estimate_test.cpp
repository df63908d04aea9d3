// The error estimate's arithmetic: Student's t against tabled values, the running moments against
// a two-pass variance, the bias weight against the disc integrals it is derived from, and the
// image norm on pixels whose errors are known.
#include "ppm/error_estimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace ppm {
namespace {

TEST(StudentT, MatchesTabledQuantiles) {
  struct Row {
    double confidence, dof, t;
  };
  // Two-sided quantiles from statistical tables.
  const Row rows[] = {{0.95, 1, 12.706}, {0.95, 2, 4.303}, {0.95, 3, 3.182}, {0.95, 10, 2.228},
                      {0.95, 30, 2.042}, {0.99, 5, 4.032}, {0.99, 3, 5.841}, {0.5, 20, 0.687},
                      {0.9, 7, 1.895},   {0.95, 1000, 1.962}};
  for (const Row& r : rows) EXPECT_NEAR(student_t_quantile(r.confidence, r.dof), r.t, 0.01 * r.t) << r.dof;
  EXPECT_THROW(student_t_quantile(1.0, 5), std::invalid_argument);
  EXPECT_THROW(student_t_quantile(0.9, 0.5), std::invalid_argument);
}

TEST(RunningMoments, MatchTwoPassMeanAndVarianceOverManySamples) {
  std::mt19937 gen(7);
  std::normal_distribution<double> normal(1000.0, 0.5);  // a large mean: sums of squares would cancel
  RunningMoments m{};
  std::vector<double> xs;
  for (int i = 1; i <= 20000; ++i) {
    xs.push_back(normal(gen));
    m.add(xs.back(), static_cast<float>(i));
  }
  double mean = 0.0, ss = 0.0;
  for (double x : xs) mean += x;
  mean /= xs.size();
  for (double x : xs) ss += (x - mean) * (x - mean);
  const double n = xs.size();
  EXPECT_NEAR(m.mean, mean, 1e-5 * mean);  // float: about sqrt(n) roundings of 6e-8
  EXPECT_NEAR(m.variance_of_mean(n), ss / ((n - 1) * n), 0.02 * ss / ((n - 1) * n));
}

// Over a disc of radius r the weights integrate to 0 against a constant and to r^2 Lap(L) / 8 times
// the disc's area against a quadratic: the bias of the disc's average.
TEST(BiasWeight, GivesTheDiscAveragesBiasForQuadratics) {
  const double r = 0.3, r2 = r * r;
  const int n = 800;
  double constant = 0.0, quadratic = 0.0, average_minus_centre = 0.0;
  int inside = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = ((i + 0.5) / n * 2.0 - 1.0) * r, y = ((j + 0.5) / n * 2.0 - 1.0) * r;
      const double d2 = x * x + y * y;
      if (d2 > r2) continue;
      ++inside;
      const double L = 2.0 * x * x + 0.5 * y * y + x * y;  // Lap(L) = 5; L(0) = 0
      constant += bias_weight(d2, r2);
      quadratic += L * bias_weight(d2, r2);
      average_minus_centre += L;
    }
  EXPECT_NEAR(constant / inside, 0.0, 1e-3);
  EXPECT_NEAR(quadratic / inside, r2 * 5.0 / 8.0, 1e-3 * r2);
  EXPECT_NEAR(average_minus_centre / inside, r2 * 5.0 / 8.0, 1e-3 * r2);
}

// The same over a ball of radius r: the weights integrate to 0 against a constant and to r^2 Lap(L)
// / 10 times the ball's volume against a quadratic, the bias of the ball's average.
TEST(BiasWeight, GivesTheBallsAverageBiasForQuadratics) {
  const double r = 0.3, r2 = r * r;
  const int n = 120;
  double constant = 0.0, quadratic = 0.0, summed = 0.0, average_minus_centre = 0.0;
  int inside = 0;
  auto at = [&](int i) { return ((i + 0.5) / n * 2.0 - 1.0) * r; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double x = at(i), y = at(j), z = at(k), d2 = x * x + y * y + z * z;
        if (d2 > r2) continue;
        ++inside;
        const double L = 2.0 * x * x + 0.5 * y * y - z * z + x * y + 3.0 * y * z + z;  // Lap(L) = 3; L(0) = 0
        constant += bias_weight_in_ball(d2, r2);
        quadratic += L * bias_weight_in_ball(d2, r2);
        summed += bias_sum_in_ball(Color(L), Color(L * d2), r2).x;
        average_minus_centre += L;
      }
  EXPECT_NEAR(constant / inside, 0.0, 2e-3);
  EXPECT_NEAR(quadratic / inside, r2 * 3.0 / 10.0, 2e-3 * r2);
  EXPECT_NEAR(summed / inside, quadratic / inside, 1e-9 * r2);
  EXPECT_NEAR(average_minus_centre / inside, r2 * 3.0 / 10.0, 2e-3 * r2);
}

PixelErrorStats pixel_of(const std::vector<double>& values, double bias) {
  PixelErrorStats s{};
  uint64_t pass = 0;
  for (double v : values) s.add(v, bias, ++pass);
  return s;
}

TEST(PixelError, NoiseIsTTimesTheMeansStandardDeviation) {
  const PixelErrorStats s = pixel_of({1.0, 2.0, 3.0, 4.0}, 0.0);
  const double t = student_t_quantile(0.95, 3);
  const PixelError e = pixel_error(s, 4, t);
  EXPECT_NEAR(e.value, 2.5, 1e-6);
  EXPECT_NEAR(e.sd, std::sqrt((1.25 * 4 / 3) / 4), 1e-6);  // sample variance 5/3, of the mean / 4
  EXPECT_NEAR(e.noise, t * e.sd, 1e-9);
  EXPECT_TRUE(std::isinf(pixel_error(pixel_of({1.0}, 0.0), 1, t).noise));  // one pass: no noise estimate
}

TEST(PixelError, TheEyeSamplesSpreadCountsWhereItExceedsThePassesNoise) {
  const PixelErrorStats s = pixel_of({1.0, 2.0, 3.0, 4.0}, 0.0);  // noise variance of the mean 5/12
  const double t = student_t_quantile(0.95, 3);
  EXPECT_NEAR(pixel_error(s, 4, t, 0.1).sd, std::sqrt(5.0 / 12.0), 1e-6);  // within the noise: the noise
  EXPECT_NEAR(pixel_error(s, 4, t, 2.0).sd, std::sqrt(2.0), 1e-6);          // beyond it: the samples' spread
  const ImageError image = image_error({s}, ErrorPasses{4, 0}, 0.95, {2.0f});
  EXPECT_NEAR(image.anti_aliasing, std::sqrt(2.0 - 5.0 / 12.0) / 2.5, 1e-6);
  EXPECT_EQ(image_error({s}, ErrorPasses{4, 0}, 0.95).anti_aliasing, 0.0);
}

TEST(PixelError, ABiasEstimateWithinItsOwnNoiseCountsAsNone) {
  PixelErrorStats noisy{}, steady{};
  const double biases[] = {0.3, -0.2, 0.25, -0.35, 0.1, -0.05};
  uint64_t pass = 0;
  for (double b : biases) ++pass, noisy.add(1.0, b, pass), steady.add(1.0, 0.2, pass);
  EXPECT_EQ(pixel_error(noisy, pass, 2.0).bias, 0.0);
  EXPECT_NEAR(pixel_error(steady, pass, 2.0).bias, 0.2, 1e-6);
}

TEST(PixelError, MeanAbsoluteErrorIsTheFoldedNormalsMean) {
  PixelError e;
  e.sd = 2.0;
  EXPECT_NEAR(e.mean_absolute(), 2.0 * std::sqrt(2.0 / M_PI), 1e-12);
  e.bias = -20.0;  // bias far above the noise: its magnitude
  EXPECT_NEAR(e.mean_absolute(), 20.0, 1e-9);
  e.bias = 1.0;  // E|N(1, 4)| by quadrature
  double sum = 0.0, weight = 0.0;
  for (int i = -40000; i <= 40000; ++i) {
    const double x = i * 1e-3, p = std::exp(-0.5 * (x - 1.0) * (x - 1.0) / 4.0);
    sum += std::fabs(x) * p;
    weight += p;
  }
  EXPECT_NEAR(e.mean_absolute(), sum / weight, 1e-6);
}

TEST(ImageError, IsTheMeanAbsoluteErrorOverTheMeanValue) {
  // Two pixels, no noise, biases 0.1 and 0.3 on values 1 and 3: (0.1 + 0.3) / 4.
  std::vector<PixelErrorStats> pixels{pixel_of({1.0, 1.0, 1.0}, 0.1), pixel_of({3.0, 3.0, 3.0}, -0.3)};
  const ImageError e = image_error(pixels, ErrorPasses{3, 0}, 0.95);
  EXPECT_NEAR(e.relative, 0.1, 1e-6);
  EXPECT_NEAR(e.bias, 0.1, 1e-6);
  EXPECT_NEAR(e.noise, 0.0, 1e-9);
  EXPECT_GE(e.bound, e.relative);
  EXPECT_NEAR(e.pixel_p95, 0.1, 0.003);  // both pixels' bounds are 10% of their values
  // Before two passes nothing is known; a black image has no relative error.
  EXPECT_TRUE(std::isinf(image_error({pixel_of({1.0}, 0.0)}, ErrorPasses{1, 0}, 0.95).bound));
  EXPECT_EQ(image_error({pixel_of({0.0, 0.0}, 0.0)}, ErrorPasses{2, 0}, 0.95).bound, 0.0);
  // A pass in progress: the first pixel has three passes, the second two.
  EXPECT_EQ(ErrorPasses({2, 1}).of(0), 3u);
  EXPECT_EQ(ErrorPasses({2, 1}).of(1), 2u);
}

}  // namespace
}  // namespace ppm
