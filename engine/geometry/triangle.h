// Ray/triangle intersection (Möller & Trumbore 1997) in double precision, on a
// triangle stored as one vertex and two edges so the test needs no indexing.
#pragma once

#include "geometry/ray.h"
#include "math/aabb.h"

namespace ppm {

struct TrianglePrim {
  Vec3 v0, e1, e2;  // v1 = v0 + e1, v2 = v0 + e2
};

// Barycentric slack: Möller-Trumbore rounds u and v independently in the two
// triangles of a shared edge, so a ray through the edge could be rejected by
// both (measured: 3-15 of 2,424 rays from inside a closed cube aimed at its
// edges escaped). 1e-12 of the triangle is far below any visible size.
constexpr double kBarycentricSlack = 1e-12;

// Returns true and sets t, (b1, b2) barycentrics of v1 and v2 for a hit with 0 < t < tmax.
inline bool intersect_triangle(const TrianglePrim& tri, const Ray& ray, double tmax, double& t,
                               double& b1, double& b2) {
  const Vec3 p = glm::cross(ray.direction, tri.e2);
  const double det = glm::dot(tri.e1, p);
  if (det == 0.0 || !std::isfinite(det)) return false;  // parallel, or degenerate triangle
  const double inv = 1.0 / det;
  const Vec3 s = ray.origin - tri.v0;
  const double u = glm::dot(s, p) * inv;
  if (u < -kBarycentricSlack || u > 1.0 + kBarycentricSlack) return false;
  const Vec3 q = glm::cross(s, tri.e1);
  const double v = glm::dot(ray.direction, q) * inv;
  if (v < -kBarycentricSlack || u + v > 1.0 + kBarycentricSlack) return false;
  const double tt = glm::dot(tri.e2, q) * inv;
  if (!(tt > 0.0 && tt < tmax)) return false;
  t = tt;
  b1 = u;
  b2 = v;
  return true;
}

inline Vec3 triangle_normal(const TrianglePrim& tri) {
  const Vec3 n = glm::cross(tri.e1, tri.e2);
  const double len = glm::length(n);
  return len > 0.0 ? n / len : Vec3(0.0, 0.0, 1.0);
}

// The triangle's bounding box (its corners as the intersection test computes them).
inline Aabb triangle_box(const TrianglePrim& tri) {
  Aabb b;
  b.grow(tri.v0);
  b.grow(tri.v0 + tri.e1);
  b.grow(tri.v0 + tri.e2);
  return b;
}

inline double triangle_area(const TrianglePrim& tri) {
  return 0.5 * glm::length(glm::cross(tri.e1, tri.e2));
}

}  // namespace ppm
