// What the lobe and closure tests share: a flat surface facing +Z and directions above or below it.
#pragma once

#include "shading/scatter.h"

#include <cmath>

namespace ppm {

inline const SurfacePoint kFlat{Vec3(0, 0, 1), Vec3(0, 0, 1), Color(1.0)};

// The unit direction at cos(theta) from +Z (negative: below), turned by phi about Z.
inline Vec3 direction(double cos_theta, double phi = 0.0) {
  const double s = std::sqrt(std::fmax(0.0, 1.0 - cos_theta * cos_theta));
  return Vec3(s * std::cos(phi), s * std::sin(phi), cos_theta);
}

}  // namespace ppm
