// Per-pixel statistics of stochastic progressive photon mapping (Hachisuka &
// Jensen 2009): the eye samples change every pass, so radius, photon count and
// flux live with the pixel instead of with a hit point. Emitted and direct
// light are running sums over passes.
#pragma once

#include "math/types.h"

namespace ppm {

struct PixelStats {
  double r2 = 0.0;       // 0 until the pixel's first hit point sets the initial radius
  double n = 0.0;
  uint32_t m = 0;
  Color tau{0.0}, tau_m{0.0};
  Color direct{0.0};     // sum over passes
  Color emitted{0.0};    // sum over passes
};

}  // namespace ppm
