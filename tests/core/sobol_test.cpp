// The scrambled Sobol' sequence (math/sobol.h): its first 2^m points put one point in every
// elementary box of area 2^-m whatever the scramble (the (0,2)-sequence property that makes a small
// feature of a pixel be found in proportion to its area), and each point is uniform over the
// scrambles (so that averages over it are unbiased).
#include "math/sobol.h"

#include <gtest/gtest.h>

#include <vector>

namespace ppm {
namespace {

TEST(Sobol, UnscrambledStartsAsTheTextbookSequence) {
  const double expected[4][2] = {{0.0, 0.0}, {0.5, 0.5}, {0.25, 0.75}, {0.75, 0.25}};
  for (uint32_t i = 0; i < 4; ++i) {
    uint32_t x, y;
    sobol_2d_bits(i, x, y);
    EXPECT_EQ(x * (1.0 / 4294967296.0), expected[i][0]) << i;
    EXPECT_EQ(y * (1.0 / 4294967296.0), expected[i][1]) << i;
  }
}

// Every elementary box of area 2^-m (2^a columns by 2^(m-a) rows, for every a) holds exactly one of
// the points with index in [k 2^m, (k+1) 2^m).
void expect_one_point_per_elementary_box(uint64_t seed, int m, uint32_t first) {
  const uint32_t n = 1u << m;
  std::vector<Vec2> points(n);
  for (uint32_t i = 0; i < n; ++i) points[i] = sobol_owen_2d(first + i, seed);
  for (int a = 0; a <= m; ++a) {
    const uint32_t cols = 1u << a, rows = 1u << (m - a);
    std::vector<int> count(n, 0);
    for (const Vec2& p : points) {
      ASSERT_GE(p.x, 0.0);
      ASSERT_LT(p.x, 1.0);
      ASSERT_GE(p.y, 0.0);
      ASSERT_LT(p.y, 1.0);
      ++count[static_cast<uint32_t>(p.y * rows) * cols + static_cast<uint32_t>(p.x * cols)];
    }
    for (uint32_t b = 0; b < n; ++b) ASSERT_EQ(count[b], 1) << "seed " << seed << " m " << m << " a " << a;
  }
}

TEST(Sobol, ScrambledPointsStratifyEveryElementaryBox) {
  for (uint64_t seed : {0ull, 1ull, 12345ull, 0xdeadbeefcafeull})
    for (int m = 0; m <= 10; ++m) {
      expect_one_point_per_elementary_box(seed, m, 0);
      expect_one_point_per_elementary_box(seed, m, 3u << m);  // any aligned block, not only the first
    }
}

TEST(Sobol, EachPointIsUniformOverTheScrambles) {
  // Point i over 2^16 seeds: the counts in 16 x 16 cells are multinomial; a chi-square with 255
  // degrees of freedom has mean 255 and standard deviation 22.6, so 380 is more than 5 of them.
  constexpr int kSeeds = 1 << 16, kCells = 16;
  for (uint32_t index : {0u, 1u, 5u, 1000u}) {
    std::vector<int> count(kCells * kCells, 0);
    for (int s = 0; s < kSeeds; ++s) {
      const Vec2 p = sobol_owen_2d(index, static_cast<uint64_t>(s));
      ++count[static_cast<int>(p.y * kCells) * kCells + static_cast<int>(p.x * kCells)];
    }
    const double expected = double(kSeeds) / (kCells * kCells);
    double chi2 = 0.0;
    for (int c : count) chi2 += (c - expected) * (c - expected) / expected;
    EXPECT_LT(chi2, 380.0) << "index " << index;
  }
}

TEST(Sobol, DifferentSeedsGiveDifferentSequences) {
  int same = 0;
  for (uint32_t i = 0; i < 64; ++i) same += sobol_owen_2d(i, 7) == sobol_owen_2d(i, 8);
  EXPECT_EQ(same, 0);
}

}  // namespace
}  // namespace ppm
