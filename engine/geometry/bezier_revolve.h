// Surface of revolution of a 2-D Bézier profile (radius, height) about the
// local Z axis, placed in the world by an affine matrix. Ray intersection is
// exact up to rounding: the ray/surface condition becomes one polynomial in
// the profile parameter (Bernstein basis, no division by any direction
// component), all its roots in [0, 1] are isolated by subdivision, and each
// candidate is polished by Newton on the (profile parameter, ray parameter)
// pair. See bezier_revolve.cpp for the formulation.
#pragma once

#include "geometry/ray.h"
#include "math/aabb.h"
#include "math/types.h"

#include <cstddef>
#include <vector>

namespace ppm {

enum class BezierProfileKind { SingleCurve, CubicChain };

class BezierRevolve {
 public:
  static constexpr int kMaxDegree = 8;

  // Throws std::invalid_argument naming the offending point and field, or the
  // matrix problem: NaN/Inf, fewer than 2 points, degree above 8, chain point
  // count not 3k+1, non-affine or singular matrix, all points identical.
  // A radius may be negative: the surface is then that of |r|, with the
  // orientation continuous where the profile crosses the axis.
  BezierRevolve(std::vector<Vec2> points, BezierProfileKind kind, const Mat4& object_to_world);

  size_t segment_count() const { return segments_.size(); }
  // World box of segment s's swept surface (union of 8 sub-cylinder boxes).
  Aabb segment_bounds(size_t s) const { return segments_[s].bounds; }

  // Nearest hit with segment s of the world ray (unit direction) with
  // tmin < t < tmax. Fills t, position, geometric/shading normal (unit, world;
  // outside = right of the profile's direction of travel in the (r, z) plane),
  // uv = (profile parameter over the whole profile, angle / 2pi in [0, 1)).
  bool intersect_segment(size_t s, const Ray& ray, double tmin, double tmax, Hit& hit) const;

 private:
  // Per-segment data in the local frame; heights are stored relative to the
  // middle of the segment's height range so coefficients stay small.
  struct Segment {
    int n = 0;                        // degree
    double r[kMaxDegree + 1] = {};    // radii
    double z[kMaxDegree + 1] = {};    // heights minus zc
    double zc = 0.0;                  // middle of the height range
    double zlo = 0.0, zhi = 0.0;      // exact height range (minus zc)
    double rmin = 0.0, rmax = 0.0;    // exact range of |r(t)|
    double scale = 0.0;               // local length scale for tolerances
    double z1[2 * kMaxDegree + 1] = {};  // z elevated to degree 2n
    double z2[2 * kMaxDegree + 1] = {};  // z^2
    double r2[2 * kMaxDegree + 1] = {};  // r^2
    double max_z1 = 0.0, max_z2 = 0.0, max_r2 = 0.0;
    bool degenerate = false;          // all control points equal: no area
    Aabb bounds;
  };

  struct LocalRay;
  struct Candidate;

  Segment make_segment(const Vec2* p, int n) const;
  bool local_ray(const Segment& g, const Ray& ray, double tmin, double tmax, LocalRay& lr) const;
  void solve(const Segment& g, const LocalRay& lr, Candidate& best) const;
  void start_newton(const Segment& g, const LocalRay& lr, double t, Candidate& best) const;
  void try_candidate(const Segment& g, const LocalRay& lr, double t, double s,
                     Candidate& best) const;
  Vec3 local_normal(const Segment& g, double t, double x, double y) const;

  std::vector<Segment> segments_;
  Mat4 to_world_;
  Mat4 to_local_;
  glm::dmat3 normal_to_world_;  // inverse transpose of the linear part
};

}  // namespace ppm
