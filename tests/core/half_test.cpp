// to_half / from_half against the definition: every finite half decodes to
// the value glm gives, and floats round to the nearest half, ties to even.
#include "math/half.h"

#include <glm/gtc/packing.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ppm {
namespace {

bool finite_half(uint32_t h) { return ((h >> 10) & 0x1fu) != 0x1fu; }

TEST(Half, EveryFiniteHalfDecodesExactlyAndRoundTrips) {
  for (uint32_t h = 0; h <= 0xffffu; ++h) {
    if (!finite_half(h)) continue;
    const float f = from_half(static_cast<uint16_t>(h));
    ASSERT_EQ(f, glm::unpackHalf1x16(static_cast<uint16_t>(h))) << std::hex << h;
    ASSERT_EQ(std::signbit(f), (h & 0x8000u) != 0) << std::hex << h;
    ASSERT_EQ(to_half(f), h) << std::hex << h;
  }
}

// The nearest half to f, found by comparing the candidates around to_half(f).
void expect_nearest(float f) {
  const uint16_t h = to_half(f);
  const double error = std::fabs(double(from_half(h)) - f);
  for (int step : {-1, 1}) {
    const uint32_t n = static_cast<uint32_t>(h) + step;
    if (n > 0xffffu || !finite_half(n) || ((n ^ h) & 0x8000u)) continue;  // no neighbour of the same sign
    const double other = std::fabs(double(from_half(static_cast<uint16_t>(n))) - f);
    ASSERT_LE(error, other) << f;
    if (error == other) ASSERT_EQ(h & 1u, 0u) << "a tie must go to the even half: " << f;
  }
}

TEST(Half, FloatsRoundToTheNearestHalfTiesToEven) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> exponent(-30.0f, 16.0f), sign(-1.0f, 1.0f);
  for (int i = 0; i < 200000; ++i) expect_nearest(std::copysign(std::exp2(exponent(rng)), sign(rng)));
  for (uint32_t h = 0; h < 0x7bffu; ++h) {  // the midpoints between neighbouring halves: all ties
    const float mid = 0.5f * (from_half(static_cast<uint16_t>(h)) + from_half(static_cast<uint16_t>(h + 1)));
    expect_nearest(mid);
    expect_nearest(-mid);
  }
}

TEST(Half, OutOfRangeClampsToTheLargestHalf) {
  EXPECT_EQ(from_half(to_half(1e30f)), kMaxHalf);
  EXPECT_EQ(from_half(to_half(-INFINITY)), -kMaxHalf);
  EXPECT_EQ(from_half(to_half(65519.0f)), kMaxHalf);
  EXPECT_EQ(from_half(to_half(1e-9f)), 0.0f);
}

}  // namespace
}  // namespace ppm
