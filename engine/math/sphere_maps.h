// Directions to image coordinates on the sphere around the scene, as Cycles maps an environment
// image: equirectangular (longitude across, latitude up) and the mirror ball (a photo of a
// reflective sphere seen along +Y). Shared by the world's light and the Environment Texture node.
#pragma once

#include "math/types.h"

#include <cmath>

namespace ppm {

inline Vec2 equirectangular_uv(const Vec3& dir) {
  const double u = 0.5 - std::atan2(dir.y, dir.x) / (2.0 * kPi);
  const double v = 0.5 + std::atan2(dir.z, std::hypot(dir.x, dir.y)) / kPi;
  return Vec2(u, v);
}

inline Vec2 mirror_ball_uv(const Vec3& dir) {
  Vec3 d = dir;
  d.y -= 1.0;
  const double div = 2.0 * std::sqrt(std::fmax(-0.5 * d.y, 0.0));
  if (div > 0.0) d /= div;
  return Vec2(0.5 * (d.x + 1.0), 0.5 * (d.z + 1.0));
}

}  // namespace ppm
