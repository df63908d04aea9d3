// Adaptive eye sampling's allocation: samples in proportion to each pixel's spread of pass values,
// at least one, at most the maximum.
#include "ppm/adaptive_samples.h"

#include <gtest/gtest.h>

#include <vector>

namespace ppm {
namespace {

// A pixel whose `passes` pass values alternate between -sigma and +sigma around 1.
PixelErrorStats pixel_with_spread(double sigma, uint64_t passes) {
  PixelErrorStats s{};
  for (uint64_t j = 1; j <= passes; ++j) s.add(1.0 + (j % 2 ? sigma : -sigma), 0.0, j);
  return s;
}

TEST(AdaptiveSamples, InProportionToTheSpreadAtLeastOneAtMostTheMaximum) {
  const uint64_t passes = 10;
  const std::vector<PixelErrorStats> pixels = {pixel_with_spread(0.0, passes), pixel_with_spread(1.0, passes),
                                               pixel_with_spread(3.0, passes), pixel_with_spread(12.0, passes)};
  std::vector<uint8_t> samples;
  allocate_eye_samples(pixels, passes, 8, samples);
  // Mean spread 4: 0 -> 1 (the least), 1 -> ceil(0.25) = 1, 3 -> ceil(0.75) = 1, 12 -> 3.
  EXPECT_EQ(samples, (std::vector<uint8_t>{1, 1, 1, 3}));
  allocate_eye_samples(pixels, passes, 2, samples);
  EXPECT_EQ(samples, (std::vector<uint8_t>{1, 1, 1, 2}));  // clamped to the maximum
}

TEST(AdaptiveSamples, OneEverywhereWithoutAnEstimate) {
  std::vector<uint8_t> samples;
  allocate_eye_samples({pixel_with_spread(1.0, 1), pixel_with_spread(5.0, 1)}, 1, 8, samples);
  EXPECT_EQ(samples, (std::vector<uint8_t>{1, 1}));  // one pass: no spread known
  allocate_eye_samples({pixel_with_spread(0.0, 4), pixel_with_spread(0.0, 4)}, 4, 8, samples);
  EXPECT_EQ(samples, (std::vector<uint8_t>{1, 1}));  // no noise anywhere
}

}  // namespace
}  // namespace ppm
