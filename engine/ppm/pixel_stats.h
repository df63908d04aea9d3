// Per-pixel statistics of stochastic progressive photon mapping (Hachisuka &
// Jensen 2009): the eye samples change every pass, so radius, photon count and
// flux live with the pixel instead of with a hit point. Emitted and direct
// light are running sums over passes.
#pragma once

#include "ppm/hit_point.h"

namespace ppm {

struct PixelStats {
  double r2 = 0.0;       // 0 until the pixel's first hit point sets the initial radius
  HitPointStats stats{}; // n, m, tau, tau_m as for a fixed hit point; direct: sum over passes
  Color emitted{0.0};    // sum over passes
  double transparency = 0.0;  // sum over passes
};

}  // namespace ppm
