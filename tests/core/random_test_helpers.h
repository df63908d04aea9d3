// Random test inputs shared by the C++ tests.
#pragma once

#include "math/rng.h"
#include "math/types.h"

namespace ppm {

// A uniform point in the unit cube centred at the origin.
inline Vec3 unit_cube(Rng& rng) { return Vec3(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3(0.5); }

}  // namespace ppm
