// Axis-aligned bounding box and the slab test used by the BVH.
#pragma once

#include "math/float_bounds.h"
#include "math/types.h"

#include <algorithm>
#include <limits>

namespace ppm {

struct Aabb {
  Vec3 lo{kInf};
  Vec3 hi{-kInf};

  void grow(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  Vec3 center() const { return 0.5 * (lo + hi); }
  Vec3 extent() const { return hi - lo; }
  double half_area() const {
    if (empty()) return 0.0;
    const Vec3 e = extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  // Whether the closed boxes share a point.
  bool touches(const Aabb& b) const { return glm::all(glm::lessThanEqual(glm::max(lo, b.lo), glm::min(hi, b.hi))); }
  int longest_axis() const {
    const Vec3 e = extent();
    return e.x > e.y ? (e.x > e.z ? 0 : 2) : (e.y > e.z ? 1 : 2);
  }
};

// The box holding `box`'s eight corners through the affine map `m`.
inline Aabb transformed(const Aabb& box, const glm::dmat4& m) {
  Aabb out;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                 (corner & 4) ? box.hi.z : box.lo.z);
    out.grow(Vec3(m * glm::dvec4(p, 1.0)));
  }
  return out;
}

// A box in float that contains the double box it was made from (its bounds rounded outwards,
// float_bounds.h): half the bytes, for what ends in the BVH's float boxes anyway.
struct FloatAabb {
  Vec3f lo{std::numeric_limits<float>::infinity()};
  Vec3f hi{-std::numeric_limits<float>::infinity()};

  static FloatAabb around(const Aabb& b) {
    FloatAabb f;
    for (int a = 0; a < 3; ++a) {
      f.lo[a] = b.lo[a] == kInf ? f.lo[a] : float_down(b.lo[a]);  // an empty box stays empty
      f.hi[a] = b.hi[a] == -kInf ? f.hi[a] : float_up(b.hi[a]);
    }
    return f;
  }
  void grow(const FloatAabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  Aabb to_double() const { return Aabb{Vec3(lo), Vec3(hi)}; }
  double half_area() const { return to_double().half_area(); }
};

// Slab test with precomputed reciprocal direction. Returns the entry distance
// or kInf. Robust to zero direction components (inf * 0 handled by min/max
// ordering because the box is never degenerate-NaN).
// The part [t0, t1] of the ray's [0, tmax] inside the box (empty: t0 > t1).
inline void slab_interval(const Aabb& box, const Vec3& origin, const Vec3& inv_dir, double tmax, double& t0,
                          double& t1) {
  t0 = 0.0;
  t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    double tn = (box.lo[a] - origin[a]) * inv_dir[a];
    double tf = (box.hi[a] - origin[a]) * inv_dir[a];
    if (tn > tf) std::swap(tn, tf);
    // NaN (0 * inf when the origin lies on a slab plane) must not shrink the interval.
    t0 = tn > t0 ? tn : t0;
    t1 = tf < t1 ? tf : t1;
  }
}

inline double slab_entry(const Aabb& box, const Vec3& origin, const Vec3& inv_dir, double tmax) {
  double t0, t1;
  slab_interval(box, origin, inv_dir, tmax, t0, t1);
  // Conservative widening by a few ulps keeps rays along box faces from slipping through.
  return t0 <= t1 * (1.0 + 4e-16) ? t0 : kInf;
}

}  // namespace ppm
