// Warps from the unit square to the directions and points the renderer samples,
// each with its density. Tested in tests/core/sampling_test.cpp by integration.
#pragma once

#include "math/types.h"

namespace ppm {

// Cosine-weighted hemisphere around +Z; pdf = cos(theta)/pi.
inline Vec3 sample_cosine_hemisphere(double u1, double u2) {
  const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(max_ignoring_nan(0.0, 1.0 - u1)));
}

// Uniform on the hemisphere around +Z; pdf = 1/(2 pi).
inline Vec3 sample_uniform_hemisphere(double u1, double u2) {
  const double z = u1;
  const double r = std::sqrt(max_ignoring_nan(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Uniform on the unit sphere; pdf = 1/(4 pi).
inline Vec3 sample_uniform_sphere(double u1, double u2) {
  const double z = 1.0 - 2.0 * u1;
  const double r = std::sqrt(max_ignoring_nan(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Uniform in the cone of directions within acos(cos_max) of +Z; pdf = 1/(2 pi (1 - cos_max)).
inline Vec3 sample_uniform_cone(double u1, double u2, double cos_max) {
  const double z = 1.0 - u1 * (1.0 - cos_max);
  const double r = std::sqrt(max_ignoring_nan(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Uniform on the unit disk (concentric map, Shirley & Chiu 1997); pdf = 1/pi.
inline Vec2 sample_uniform_disk(double u1, double u2) {
  const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
  if (a == 0.0 && b == 0.0) return Vec2(0.0);
  double r, phi;
  if (std::fabs(a) > std::fabs(b)) {
    r = a;
    phi = (kPi / 4.0) * (b / a);
  } else {
    r = b;
    phi = (kPi / 2.0) - (kPi / 4.0) * (a / b);
  }
  return Vec2(r * std::cos(phi), r * std::sin(phi));
}

// Uniform on a triangle: barycentrics (b1, b2) of vertices 1 and 2 (Heitz 2019 low-distortion map).
inline Vec2 sample_uniform_triangle(double u1, double u2) {
  double b0, b1;
  if (u1 < u2) {
    b0 = u1 / 2.0;
    b1 = u2 - b0;
  } else {
    b1 = u2 / 2.0;
    b0 = u1 - b1;
  }
  return Vec2(b1, 1.0 - b0 - b1);
}

// Local frame helpers: `to_world` maps a +Z-hemisphere vector into the frame of n.
inline Vec3 to_world(const Vec3& local, const Vec3& n) {
  Vec3 t, b;
  make_basis(n, t, b);
  return local.x * t + local.y * b + local.z * n;
}

}  // namespace ppm
