// Random test inputs shared by the C++ tests, and how many the slowest statistical ones draw.
#pragma once

#include "math/rng.h"
#include "math/types.h"

#include <algorithm>
#include <cstdlib>

namespace ppm {

// The sample (or ray, or trial) count `n` of one of the slowest statistical tests, divided by the
// environment's PPM_TEST_SAMPLE_DIVISOR (1 where unset). `make test-cross` sets 4: under qemu-user
// floating point runs 30-40 times slower than here, and those tests took 12 of its 14 minutes. Each
// tolerance still holds with a quarter of the samples (checked here and under qemu).
inline int test_samples(int n) {
  static const int divisor = [] {
    const char* text = std::getenv("PPM_TEST_SAMPLE_DIVISOR");
    return text ? std::max(1, std::atoi(text)) : 1;
  }();
  return std::max(1, n / divisor);
}

// A uniform point in the unit cube centred at the origin.
inline Vec3 unit_cube(Rng& rng) { return Vec3(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3(0.5); }

}  // namespace ppm
