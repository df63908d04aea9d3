// Ray/sphere intersection with the numerically stable quadratic of Haines et
// al. ("Precision improvements for ray/sphere intersection", Ray Tracing Gems
// 2019): the discriminant is formed from the ray's closest approach, so large
// distances and small spheres do not cancel catastrophically.
#pragma once

#include "geometry/ray.h"

namespace ppm {

struct SpherePrim {
  Vec3 center;
  double radius;
};

// Nearest root with 0 < t < tmax.
inline bool intersect_sphere(const SpherePrim& s, const Ray& ray, double tmax, double& t) {
  const Vec3 f = ray.origin - s.center;
  const double b = glm::dot(f, ray.direction);
  const Vec3 l = f - b * ray.direction;
  const double r2 = s.radius * s.radius;
  const double disc = r2 - glm::dot(l, l);
  if (disc < 0.0) return false;
  const double c = glm::dot(f, f) - r2;
  const double q = -b - std::copysign(std::sqrt(disc), b);
  double t0 = q != 0.0 ? c / q : 0.0, t1 = q;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > 0.0 && t0 < tmax) {
    t = t0;
    return true;
  }
  if (t1 > 0.0 && t1 < tmax) {
    t = t1;
    return true;
  }
  return false;
}

}  // namespace ppm
