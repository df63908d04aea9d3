// The global radius schedule of probabilistic progressive photon mapping (Knaus & Zwicker 2011,
// "Progressive Photon Mapping: A Probabilistic Approach"): pass j gathers at
//   r_j^2 = r_1^2 prod_{i=1}^{j-1} (i + alpha) / (i + 1) = r_1^2 Gamma(j + alpha) / (Gamma(1 + alpha) Gamma(j + 1)),
// r_1 the hit point's own initial radius, and the image is the mean of the passes' estimates. No
// statistic passes from one pass to the next, so any range of passes can be rendered apart (on
// another machine) and the ranges merged into exactly the image of one long render (share.h).
// The variance of pass j grows as 1 / r_j^2 and its bias shrinks as r_j^2: the mean of N passes
// has both vanish, for alpha in (0, 1).
//
// The cross-generation threshold P does not carry over: it decides per hit point when its own
// photon count lets the radius shrink, and a radius that depends on what a hit point gathered
// in earlier passes ties every pass to the ones before it. bench/README.md ("Sharded stills")
// compares the two schedules' error over passes.
#pragma once

#include <cmath>
#include <cstdint>

namespace ppm {

// r_j^2 / r_1^2 for pass j (1 for the first), alpha in (0, 1). From lgamma: its relative error is
// about 1e-16 ln Gamma(j), 1e-10 at pass 10^5; the same on every machine of one platform.
inline double global_radius_factor(uint64_t j, double alpha) {
  if (j <= 1) return 1.0;
  const double n = static_cast<double>(j);
  return std::exp(std::lgamma(n + alpha) - std::lgamma(1.0 + alpha) - std::lgamma(n + 1.0));
}

// The same in a gather region of `dimensions` (3: the sphere of a hit point in a medium). Knaus &
// Zwicker's rule is on the region's measure: the variance of pass j grows as r_j^-d and the bias
// shrinks as r_j^2, and r_j^d = r_1^d prod (i + alpha) / (i + 1) balances them (their volumetric
// photon points, d = 3), as progressive.h's rule keeps the photon density over a region of d
// dimensions. So r_j^2 / r_1^2 is the product's 2/d power: the radius shrinks with exponent 1/d
// (1/3 in a medium, 1/2 on a surface) of the same product.
inline double global_radius_factor_in(int dimensions, uint64_t j, double alpha) {
  const double factor = global_radius_factor(j, alpha);
  return dimensions == 2 ? factor : std::pow(factor, 2.0 / dimensions);
}

}  // namespace ppm
