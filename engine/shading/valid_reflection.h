// A shading normal turned so that the viewer's mirror direction stays above the surface, as
// Blender 3.x's Cycles makes every closure's normal (a normal map can tilt the normal so far that
// the view would reflect into the surface). Derived here: in the plane of ng and n, the normal
// n' = x X + z ng (X: n's direction along the surface, x = sqrt(1 - z^2)) reflects the view v to a
// direction of height t = min(0.9 v.ng, 0.01) above the surface when 2 (n'.v) z - v.ng = t; squared,
// a quadratic in u = z^2 whose roots are checked against the unsquared equation. The root nearest
// the original normal is kept; ng itself if neither holds.
#pragma once

#include "math/types.h"

#include <cmath>
#include <initializer_list>

namespace ppm {

// ng: the geometric normal, v: towards the viewer, both unit with v.ng > 0; n on ng's side.
inline Vec3 valid_reflection(const Vec3& ng, const Vec3& v, const Vec3& n) {
  const double vz = glm::dot(v, ng);
  const double t = std::fmin(0.9 * vz, 0.01);
  if (glm::dot(2.0 * glm::dot(n, v) * n - v, ng) >= t) return n;
  Vec3 along = n - glm::dot(n, ng) * ng;
  const double length = glm::length(along);
  if (!(length > 1e-12)) return ng;
  along /= length;
  const double vx = glm::dot(v, along), c = t + vz;
  const double a = vx * vx + vz * vz, b = vx * vx + c * vz;
  const double d = vx * vx * (vx * vx + 2.0 * c * vz - c * c);
  if (!(a > 0.0) || d < 0.0) return ng;
  Vec3 best = ng;
  double best_cos = -2.0;
  for (const double sign : {1.0, -1.0}) {
    const double u = (b + sign * std::sqrt(d)) / (2.0 * a);
    if (!(u > 1e-10 && u <= 1.0 + 1e-10)) continue;
    const double z = std::sqrt(std::fmin(u, 1.0)), x = std::sqrt(std::fmax(0.0, 1.0 - u));
    const Vec3 candidate = x * along + z * ng;
    const double height = glm::dot(2.0 * glm::dot(candidate, v) * candidate - v, ng);
    if (std::fabs(height - t) > 1e-6 || glm::dot(candidate, n) <= best_cos) continue;
    best = candidate;
    best_cos = glm::dot(candidate, n);
  }
  return best;
}

}  // namespace ppm
