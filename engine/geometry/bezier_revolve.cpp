// Ray intersection with surfaces of revolution of Bézier profiles.
//
// Formulation. In the local frame the ray is o + s d with d unit (the world
// distance is s / |L^-1 D|). Rotate about the axis so that the horizontal part
// of d points along e1: the ray is then (u + s sqrt(a), h, oz + s dz) with
// a = dx^2 + dy^2, u = o.e1 and h the signed distance of the ray's projection
// from the axis. It meets the circle of radius r(t) at height z(t) iff
//     z(t) = oz + s dz   and   r(t)^2 = (u + s sqrt(a))^2 + h^2.
// Eliminating s by multiplying the second equation with dz^2 (never dividing):
//     P(t) = (sqrt(a) z(t) + K)^2 + dz^2 (h^2 - r(t)^2),  K = u dz - sqrt(a) oz,
// a polynomial of degree 2n kept in the Bernstein basis (z^2, z and r^2 are
// precomputed per segment, so building P costs 2n+1 multiply-adds). P is
// valid for every direction: dz = 0 gives a (z - oz)^2, whose double roots are
// the heights the perpendicular ray stays at; a = 0 gives dz^2 (|o_xy|^2 - r^2).
//
// Conditioning. P has the same roots for all directions, but recovering s
// from a root t is direction dependent: s = (z - oz)/dz is well conditioned
// for steep rays (a <= 1/2, |dz| >= 0.707) and useless when dz -> 0, where the
// two hits of a nearly perpendicular ray have nearly the same t (a near-double
// root: intrinsic, the map hit -> t is 2-to-1 at dz = 0). For shallow rays
// s = s0 +- sqrt((r^2 - h^2)/a) is used instead (s0 = closest approach to the
// axis), the branch chosen by the height residual, both tried when the
// residual cannot tell them apart. Every candidate (t, s) is then polished by
// Newton on the 2x2 system above, whose Jacobian is singular only where the
// ray is tangent to the surface, so the final accuracy is that of the
// geometric problem, not of the elimination.
//
// Roots: the Bernstein subdivision finder (math/bernstein.h) with the noise
// bound tol = 64 eps * (sum of the magnitudes of the terms of P): it cannot
// skip a sign change and reports touching (double) roots of tangent rays. A
// touching root may hide two crossings closer than P can separate (a grazing
// ray: P's dip between them is below tol), so Newton also starts from both
// ends of the band |P| <= tol around it. A polished candidate is a hit only if
// its residual is below 1e-11 (relative): converged hits sit near 1e-15, and a
// ray passing a silhouette at a meridian gap above ~1e-11 of the segment's
// size can never be accepted. The ray origin is first moved along the ray to
// the point closest to the segment's centre, so all quantities are of the
// segment's size whatever the camera distance (the world t is recovered from
// that offset and the local length of the unit world direction).
#include "geometry/bezier_revolve.h"

#include "math/bernstein.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ppm {

namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("BezierRevolve: " + what);
}

void check_points(const std::vector<Vec2>& points, BezierProfileKind kind) {
  for (size_t i = 0; i < points.size(); ++i) {
    for (int f = 0; f < 2; ++f) {
      if (!std::isfinite(points[i][f])) {
        std::ostringstream m;
        m << "point " << i << " has a non-finite " << (f == 0 ? "radius" : "height") << " ("
          << points[i][f] << ")";
        fail(m.str());
      }
    }
  }
  const size_t n = points.size();
  if (n < 2) fail("a profile needs at least 2 points, got " + std::to_string(n));
  if (kind == BezierProfileKind::SingleCurve && n - 1 > size_t(BezierRevolve::kMaxDegree))
    fail("single curve of degree " + std::to_string(n - 1) + " (" + std::to_string(n) +
         " points) is above the maximum degree 8");
  if (kind == BezierProfileKind::CubicChain && (n - 1) % 3 != 0)
    fail("a cubic chain needs 3k+1 points (4, 7, 10, ...), got " + std::to_string(n));
  bool identical = true;
  for (size_t i = 1; i < n; ++i) identical = identical && points[i] == points[0];
  if (identical) {
    std::ostringstream m;
    m << "all " << n << " points are identical (" << points[0].x << ", " << points[0].y
      << "): the surface has no area";
    fail(m.str());
  }
}

void check_matrix(const Mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r]))
        fail("object_to_world has a non-finite entry at row " + std::to_string(r) +
             ", column " + std::to_string(c));
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
    fail("object_to_world is not affine (bottom row must be 0 0 0 1)");
  const glm::dmat3 l(m);
  const double det = glm::determinant(l);
  const double norms = glm::length(l[0]) * glm::length(l[1]) * glm::length(l[2]);
  if (!(std::fabs(det) > 1e-14 * norms)) {
    std::ostringstream msg;
    msg << "object_to_world is singular (determinant " << det << ")";
    fail(msg.str());
  }
}

double max_abs_coef(const double* c, int n) {
  double m = 0.0;
  for (int i = 0; i <= n; ++i) m = std::max(m, std::fabs(c[i]));
  return m;
}

// Parameters where r or z can take an extreme value: ends and roots of r', z'.
int critical_parameters(const double* r, const double* z, int n, double* out) {
  int k = 0;
  out[k++] = 0.0;
  out[k++] = 1.0;
  if (n >= 2) {
    for (const double* c : {r, z}) {
      double d[BezierRevolve::kMaxDegree];
      bernstein_derivative(c, n, d);
      BernsteinRoots roots;
      bernstein_roots(d, n - 1, bernstein_default_tolerance(d, n - 1), roots);
      for (int i = 0; i < roots.count; ++i) out[k++] = roots.t[i];
    }
  }
  std::sort(out, out + k);
  return k;
}

// World box of the cylinder {|xy| <= rmax, z in [zlo, zhi]} (local): the
// discs at both ends span rmax * |row i of the first two columns| along axis i.
Aabb cylinder_box(const Mat4& m, double zlo, double zhi, double rmax) {
  Aabb box;
  Vec3 e;
  for (int i = 0; i < 3; ++i) e[i] = rmax * std::sqrt(m[0][i] * m[0][i] + m[1][i] * m[1][i]);
  for (double z : {zlo, zhi}) {
    const Vec3 c = Vec3(m * glm::dvec4(0.0, 0.0, z, 1.0));
    box.grow(c - e);
    box.grow(c + e);
  }
  return box;
}

// Union of the world boxes of 8 sub-cylinders of a segment (r, z control
// values of degree n, z already relative to zc), each with the exact height
// range and max |r| of its parameter range (ends plus critical parameters).
Aabb sub_cylinder_bounds(const double* r, const double* z, int n, double zc, double scale,
                         const double* crit, int nc, const Mat4& to_world) {
  Aabb box;
  const double pad = 1e-9 * scale;
  for (int k = 0; k < 8; ++k) {
    const double a = k / 8.0, b = (k + 1) / 8.0;
    double zlo = kInf, zhi = -kInf, rmax = 0.0;
    for (int i = -2; i < nc; ++i) {
      const double t = i == -2 ? a : i == -1 ? b : crit[i];
      if (t < a || t > b) continue;
      const double zt = bernstein_eval(z, n, t);
      zlo = std::min(zlo, zt), zhi = std::max(zhi, zt);
      rmax = std::max(rmax, std::fabs(bernstein_eval(r, n, t)));
    }
    box.grow(cylinder_box(to_world, zlo - pad + zc, zhi + pad + zc, rmax + pad));
  }
  const Vec3 wpad(1e-12 * (max_abs(box.lo) + max_abs(box.hi)));
  box.lo -= wpad;
  box.hi += wpad;
  return box;
}

}  // namespace

struct BezierRevolve::LocalRay {
  Vec3 o;          // origin moved to the point closest to the segment centre
  Vec3 d;          // unit direction
  double len;      // local length of the unit world direction
  double sc;       // local ray parameter of o
  double a, sa;    // d.x^2 + d.y^2 and its square root
  double u, h;     // o along e1 = d_xy / |d_xy| and across it
  double tmin, tmax;
};

struct BezierRevolve::Candidate {
  double t = 0.0;   // segment parameter
  double s = 0.0;   // local ray parameter from LocalRay::o
  double tw = kInf; // world distance
};

BezierRevolve::BezierRevolve(std::vector<Vec2> points, BezierProfileKind kind,
                             const Mat4& object_to_world) {
  check_points(points, kind);
  check_matrix(object_to_world);
  to_world_ = object_to_world;
  to_local_ = glm::inverse(object_to_world);
  normal_to_world_ = glm::transpose(glm::dmat3(to_local_));
  if (kind == BezierProfileKind::SingleCurve) {
    segments_.push_back(make_segment(points.data(), int(points.size()) - 1));
  } else {
    for (size_t i = 0; i + 3 < points.size(); i += 3) segments_.push_back(make_segment(&points[i], 3));
  }
}

BezierRevolve::Segment BezierRevolve::make_segment(const Vec2* p, int n) const {
  Segment g;
  g.n = n;
  g.degenerate = true;
  for (int i = 0; i <= n; ++i) {
    g.r[i] = p[i].x;
    g.z[i] = p[i].y;
    g.degenerate = g.degenerate && p[i] == p[0];
  }
  double crit[4 * kMaxDegree];
  const int nc = critical_parameters(g.r, g.z, n, crit);
  g.zlo = kInf, g.zhi = -kInf, g.rmin = kInf, g.rmax = 0.0;
  for (int i = 0; i < nc; ++i) {
    const double zt = bernstein_eval(g.z, n, crit[i]), rt = std::fabs(bernstein_eval(g.r, n, crit[i]));
    g.zlo = std::min(g.zlo, zt), g.zhi = std::max(g.zhi, zt);
    g.rmin = std::min(g.rmin, rt), g.rmax = std::max(g.rmax, rt);
  }
  BernsteinRoots axis;
  bernstein_roots(g.r, n, bernstein_default_tolerance(g.r, n), axis);
  if (axis.count > 0) g.rmin = 0.0;
  g.zc = 0.5 * (g.zlo + g.zhi);
  for (int i = 0; i <= n; ++i) g.z[i] -= g.zc;
  g.zlo -= g.zc, g.zhi -= g.zc;
  g.scale = std::max(g.rmax, 0.5 * (g.zhi - g.zlo));
  if (!(g.scale > 0.0)) g.degenerate = true, g.scale = 1.0;
  bernstein_elevate(g.z, n, 2 * n, g.z1);
  bernstein_multiply(g.z, n, g.z, n, g.z2);
  bernstein_multiply(g.r, n, g.r, n, g.r2);
  g.max_z1 = max_abs_coef(g.z1, 2 * n), g.max_z2 = max_abs_coef(g.z2, 2 * n), g.max_r2 = max_abs_coef(g.r2, 2 * n);
  g.bounds = sub_cylinder_bounds(g.r, g.z, n, g.zc, g.scale, crit, nc, to_world_);
  return g;
}

// World ray -> recentred local ray, then the cheap rejections: height slab
// and the cylinder shell rmin <= |xy| <= rmax over the surviving interval.
bool BezierRevolve::local_ray(const Segment& g, const Ray& ray, double tmin, double tmax,
                              LocalRay& lr) const {
  Vec3 o = Vec3(to_local_ * glm::dvec4(ray.origin, 1.0));
  const Vec3 dl = glm::dmat3(to_local_) * ray.direction;
  lr.len = glm::length(dl);
  if (!(lr.len > 0.0) || !std::isfinite(lr.len) || !is_finite(o)) return false;
  const Vec3 d = dl * (1.0 / lr.len);
  o.z -= g.zc;
  lr.sc = -glm::dot(o, d);
  o += lr.sc * d;
  lr.o = o, lr.d = d, lr.tmin = tmin, lr.tmax = tmax;
  double s_lo = tmin * lr.len - lr.sc, s_hi = tmax * lr.len - lr.sc;
  const double pad = 1e-9 * g.scale;
  if (d.z != 0.0) {
    const double inv = 1.0 / d.z;
    double s1 = (g.zlo - pad - o.z) * inv, s2 = (g.zhi + pad - o.z) * inv;
    if (s1 > s2) std::swap(s1, s2);
    s_lo = std::max(s_lo, s1), s_hi = std::min(s_hi, s2);
  } else if (o.z < g.zlo - pad || o.z > g.zhi + pad) {
    return false;
  }
  if (!(s_lo <= s_hi)) return false;
  lr.a = d.x * d.x + d.y * d.y;
  auto rho2 = [&](double s) {
    const double x = o.x + s * d.x, y = o.y + s * d.y;
    return x * x + y * y;
  };
  const double s_near = lr.a > 0.0 ? std::clamp(-(o.x * d.x + o.y * d.y) / lr.a, s_lo, s_hi) : 0.0;
  const double rmax = g.rmax + pad;
  if (rho2(s_near) > rmax * rmax) return false;
  const double rmin = g.rmin - pad;
  if (rmin > 0.0 && std::isfinite(s_lo) && std::isfinite(s_hi) && rho2(s_lo) < rmin * rmin &&
      rho2(s_hi) < rmin * rmin)
    return false;
  lr.sa = std::sqrt(lr.a);
  const double inv_sa = lr.a > 1e-300 ? 1.0 / lr.sa : 0.0;
  const double ex = lr.a > 1e-300 ? d.x * inv_sa : 1.0, ey = d.y * inv_sa;
  lr.u = o.x * ex + o.y * ey;
  lr.h = o.x * ey - o.y * ex;
  return true;
}

void BezierRevolve::solve(const Segment& g, const LocalRay& lr, Candidate& best) const {
  const int n = g.n, m = 2 * n;
  const double dz = lr.d.z, oz = lr.o.z;
  const double k = lr.u * dz - lr.sa * oz;
  const double kz1 = 2.0 * lr.sa * k, dz2 = dz * dz;
  const double cst = k * k + dz2 * lr.h * lr.h;
  double p[2 * kMaxDegree + 1];
  for (int i = 0; i <= m; ++i) p[i] = lr.a * g.z2[i] + kz1 * g.z1[i] + cst - dz2 * g.r2[i];
  const double terms = lr.a * g.max_z2 + std::fabs(kz1) * g.max_z1 + cst + dz2 * g.max_r2;
  const double tol = 64.0 * DBL_EPSILON * terms;
  BernsteinRoots roots;
  bernstein_roots(p, m, tol, roots);
  for (int i = 0; i < roots.count; ++i) {
    const double t = roots.t[i];
    start_newton(g, lr, t, best);
    if (!roots.multiple[i]) continue;
    // A touching root may stand for two crossings closer than the noise lets
    // P separate (a grazing ray): also start from both ends of the band
    // |P| <= tol around it, so Newton reaches each crossing.
    double dp[2 * kMaxDegree], p2;
    bernstein_derivative(p, m, dp);
    bernstein_eval(dp, m - 1, t, &p2);
    const double half = std::fabs(p2) > 0.0 ? std::min(1e-2, std::sqrt(2.0 * tol / std::fabs(p2))) : 1e-4;
    if (t - half >= 0.0) start_newton(g, lr, t - half, best);
    if (t + half <= 1.0) start_newton(g, lr, t + half, best);
  }
}

// Ray parameter(s) for profile parameter t, then Newton. Steep rays: s from
// the height. Shallow rays: s from the radius, branch by the height residual,
// both branches when the residual cannot tell them apart.
void BezierRevolve::start_newton(const Segment& g, const LocalRay& lr, double t, Candidate& best) const {
  const double dz = lr.d.z, oz = lr.o.z;
  const double zt = bernstein_eval(g.z, g.n, t);
  if (lr.a <= 0.5) return try_candidate(g, lr, t, (zt - oz) / dz, best);
  const double ah = std::fabs(lr.h);
  const double rt = std::fabs(bernstein_eval(g.r, g.n, t));
  const double sig = std::sqrt(std::max(0.0, (rt - ah) * (rt + ah)) / lr.a);
  double s1 = -lr.u / lr.sa + sig, s2 = -lr.u / lr.sa - sig;
  double e1 = std::fabs(zt - oz - s1 * dz), e2 = std::fabs(zt - oz - s2 * dz);
  if (e1 > e2) std::swap(s1, s2), std::swap(e1, e2);
  try_candidate(g, lr, t, s1, best);
  if (e2 <= 1e-6 * g.scale) try_candidate(g, lr, t, s2, best);
}

// Newton on F(t, s) = (z(t) - oz - s dz, r(t)^2 - (u + s sqrt(a))^2 - h^2),
// keeping the iterate of least residual; accepted if that residual is noise.
void BezierRevolve::try_candidate(const Segment& g, const LocalRay& lr, double t, double s,
                                  Candidate& best) const {
  const double L = g.scale;
  double bt = t, bs = s, bres = kInf;
  for (int it = 0; it < 10; ++it) {
    double dr, dz;
    const double r = bernstein_eval(g.r, g.n, t, &dr);
    const double z = bernstein_eval(g.z, g.n, t, &dz);
    const double px = lr.u + s * lr.sa;
    const double f1 = z - lr.o.z - s * lr.d.z;
    const double f2 = (r - px) * (r + px) - lr.h * lr.h;
    const double res = std::fabs(f1) / L + std::fabs(f2) / (L * L);
    if (res < bres) bt = t, bs = s, bres = res;
    const double j11 = dz, j12 = -lr.d.z, j21 = 2.0 * r * dr, j22 = -2.0 * lr.sa * px;
    const double det = j11 * j22 - j12 * j21;
    if (!(std::fabs(det) > 1e-14 * (std::fabs(j11 * j22) + std::fabs(j12 * j21)))) break;
    const double dt = (-f1 * j22 + j12 * f2) / det, ds = (-j11 * f2 + j21 * f1) / det;
    // A step this small is the last: take it without re-evaluating (the
    // residual there is below the one just measured).
    if (std::fabs(dt) <= 1e-13 && std::fabs(ds) <= 1e-13 * L) {
      if (res <= bres) bt = t + dt, bs = s + ds;
      break;
    }
    t += dt, s += ds;
    if (!(t > -0.5 && t < 1.5) || !std::isfinite(s)) break;
  }
  if (!(bres <= 1e-11) || bt < -1e-10 || bt > 1.0 + 1e-10) return;
  const double tw = (lr.sc + bs) / lr.len;
  if (tw > lr.tmin && tw < lr.tmax && tw < best.tw) best.t = bt, best.s = bs, best.tw = tw;
}

// Outward normal (z' cos th, z' sin th, -r') with cos th = x / r (signed r, so
// the orientation stays continuous through the axis). Where (r', z') vanishes
// the first non-zero higher derivative gives the tangent's limit; on the axis
// the normal's limit along the profile is the axial part (0, 0, -r').
Vec3 BezierRevolve::local_normal(const Segment& g, double t, double x, double y) const {
  double cr[kMaxDegree + 1], cz[kMaxDegree + 1];
  std::copy(g.r, g.r + g.n + 1, cr);
  std::copy(g.z, g.z + g.n + 1, cz);
  double tr = 0.0, tz = 1.0;
  for (int k = 1, deg = g.n; k <= g.n; ++k, --deg) {
    bernstein_derivative(cr, deg, cr);
    bernstein_derivative(cz, deg, cz);
    const double vr = bernstein_eval(cr, deg - 1, t), vz = bernstein_eval(cz, deg - 1, t);
    if (std::sqrt(vr * vr + vz * vz) > (k == 1 ? 1e-9 : 1e-12) * g.scale) {
      const double sign = (t > 0.5 && k % 2 == 0) ? -1.0 : 1.0;  // approach t from inside
      tr = sign * vr, tz = sign * vz;
      break;
    }
  }
  const double rho = std::sqrt(x * x + y * y);  // local units: no overflow
  if (rho > 1e-12 * g.scale) {
    const double sg = bernstein_eval(g.r, g.n, t) < 0.0 ? -1.0 : 1.0;
    return Vec3(sg * tz * x / rho, sg * tz * y / rho, -tr);
  }
  return Vec3(0.0, 0.0, tr > 0.0 ? -1.0 : 1.0);
}

bool BezierRevolve::intersect_segment(size_t si, const Ray& ray, double tmin, double tmax,
                                      Hit& hit) const {
  const Segment& g = segments_[si];
  if (g.degenerate) return false;
  LocalRay lr;
  if (!local_ray(g, ray, tmin, tmax, lr)) return false;
  Candidate best;
  solve(g, lr, best);
  if (!(best.tw < kInf)) return false;
  const double t = std::clamp(best.t, 0.0, 1.0);
  const double x = lr.o.x + best.s * lr.d.x, y = lr.o.y + best.s * lr.d.y;
  Vec3 nl = local_normal(g, t, x, y);
  nl /= max_abs(nl);
  Vec3 nw = normal_to_world_ * nl;
  const double len = glm::length(nw);
  nw = len > 0.0 && std::isfinite(len) ? nw / len : Vec3(0.0, 0.0, 1.0);
  hit.t = best.tw;
  hit.position = ray.origin + best.tw * ray.direction;
  hit.geometric_normal = nw;
  hit.shading_normal = nw;
  const double u = (double(si) + t) / double(segments_.size());
  double v = std::atan2(y, x) * (0.5 / kPi);
  if (v < 0.0) v += 1.0;
  if (!(v < 1.0)) v = 0.0;
  hit.uv = Vec2(std::min(u, 1.0), v);
  return true;
}

}  // namespace ppm
