// Independent long-double reference for ray / Bézier-surface-of-revolution
// intersection, used only by the tests. It shares no code or formulation with
// engine/geometry/bezier_revolve.cpp: instead of a polynomial in the profile
// parameter it scans along the RAY. The profile is cut where z'(t) = 0 into
// pieces with monotone height; on a piece, a ray point at height z has the
// unique profile parameter t(z) (bracketed inversion), and
//     g(tau) = (distance of the ray point from the axis)^2 - r(t(z(tau)))^2
// changes sign exactly where the ray crosses the piece. g is sampled densely
// in tau (world distance), sign changes are bisected, and local extrema of the
// samples are refined by golden section so that pairs of close roots (grazing
// rays) are split or reported as near-tangent events.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace bezref {

using LD = long double;

struct V3 {
  LD x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator*(LD s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline LD dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 unit(V3 a) { return (1.0L / std::sqrt(dot(a, a))) * a; }

// Row-major 4x4 in long double, with a Gauss-Jordan inverse.
struct M4 {
  LD m[4][4];
  static M4 from_glm(const glm::dmat4& g) {
    M4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) r.m[i][j] = g[j][i];
    return r;
  }
  V3 point(V3 p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
  }
  V3 vec(V3 p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z, m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z,
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z};
  }
  V3 vec_transposed(V3 p) const {
    return {m[0][0] * p.x + m[1][0] * p.y + m[2][0] * p.z, m[0][1] * p.x + m[1][1] * p.y + m[2][1] * p.z,
            m[0][2] * p.x + m[1][2] * p.y + m[2][2] * p.z};
  }
  M4 inverse() const {
    LD a[4][8];
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 8; ++j) a[i][j] = j < 4 ? m[i][j] : (j - 4 == i ? 1 : 0);
    for (int c = 0; c < 4; ++c) {
      int p = c;
      for (int i = c + 1; i < 4; ++i)
        if (std::fabs(a[i][c]) > std::fabs(a[p][c])) p = i;
      for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[p][j]);
      const LD inv = 1.0L / a[c][c];
      for (int j = 0; j < 8; ++j) a[c][j] *= inv;
      for (int i = 0; i < 4; ++i) {
        if (i == c) continue;
        const LD f = a[i][c];
        for (int j = 0; j < 8; ++j) a[i][j] -= f * a[c][j];
      }
    }
    M4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) r.m[i][j] = a[i][j + 4];
    return r;
  }
};

// de Casteljau value of control values c[0..n] at t.
inline LD casteljau(const LD* c, int n, LD t) {
  LD w[16] = {};
  for (int i = 0; i <= n; ++i) w[i] = c[i];
  for (int k = 1; k <= n; ++k)
    for (int i = 0; i <= n - k; ++i) w[i] = (1 - t) * w[i] + t * w[i + 1];
  return w[0];
}
// Derivative d/dt of the same curve.
inline LD casteljau_d(const LD* c, int n, LD t) {
  if (n == 0) return 0;
  LD d[16] = {};
  for (int i = 0; i < n; ++i) d[i] = n * (c[i + 1] - c[i]);
  return casteljau(d, n - 1, t);
}

struct Seg {
  int n;
  LD r[9], z[9];
};

struct Piece {  // part of a segment with strictly monotone height
  int seg;
  LD t0, t1, z0, z1;  // parameter range and heights at its ends
  LD rbound;          // bound on |r| over the piece (control hull of the segment)
};

struct Profile {
  std::vector<Seg> segs;
  std::vector<Piece> pieces;
  LD scale = 0;  // max(|r|, half height range) over the profile
};

// `pts` as (r, z); `chain` = cubic chain, otherwise one curve.
inline Profile make_profile(const std::vector<glm::dvec2>& pts, bool chain) {
  Profile p;
  const int n = chain ? 3 : int(pts.size()) - 1;
  LD zlo = 1e300L, zhi = -1e300L, rmax = 0;
  for (size_t s = 0; s + n < pts.size(); s += n) {
    Seg g;
    g.n = n;
    for (int i = 0; i <= n; ++i) g.r[i] = pts[s + i].x, g.z[i] = pts[s + i].y;
    p.segs.push_back(g);
  }
  for (const auto& q : pts) zlo = std::min<LD>(zlo, q.y), zhi = std::max<LD>(zhi, q.y), rmax = std::max<LD>(rmax, std::fabs(q.x));
  p.scale = std::max(rmax, (zhi - zlo) / 2);
  for (size_t si = 0; si < p.segs.size(); ++si) {
    const Seg& g = p.segs[si];
    LD rb = 0;
    for (int i = 0; i <= g.n; ++i) rb = std::max(rb, std::fabs(g.r[i]));
    // Split at sign changes of z' found on a fine grid, bisected to the end.
    std::vector<LD> cuts{0};
    const int N = 4096;
    LD prev = casteljau_d(g.z, g.n, 0);
    for (int k = 1; k <= N; ++k) {
      const LD t = LD(k) / N, cur = casteljau_d(g.z, g.n, t);
      if ((prev < 0 && cur > 0) || (prev > 0 && cur < 0)) {
        LD a = LD(k - 1) / N, b = t;
        for (int it = 0; it < 80; ++it) {
          const LD m = (a + b) / 2;
          ((casteljau_d(g.z, g.n, m) < 0) == (prev < 0) ? a : b) = m;
        }
        cuts.push_back((a + b) / 2);
      }
      if (cur != 0) prev = cur;
    }
    cuts.push_back(1);
    for (size_t k = 0; k + 1 < cuts.size(); ++k)
      p.pieces.push_back({int(si), cuts[k], cuts[k + 1], casteljau(g.z, g.n, cuts[k]),
                          casteljau(g.z, g.n, cuts[k + 1]), rb});
  }
  return p;
}

struct Result {
  bool found = false;
  LD t = 0;            // world distance
  int seg = -1;
  LD param = 0;        // segment parameter
  V3 normal;           // world, unit, by the right-of-travel convention
  bool normal_valid = false;
  LD cos = 1;          // |direction . normal|
  LD min_event = 1e30L;  // smallest |g| / scale^2 at touches / piece ends before the hit
};

namespace detail {

struct RayL {
  V3 o, d;  // local origin and direction; parameter = world distance
};

// Profile parameter on the piece where z(t) = zq (z monotone on the piece).
inline LD invert_height(const Seg& g, const Piece& pc, LD zq) {
  LD a = pc.t0, b = pc.t1;
  const bool up = pc.z1 > pc.z0;
  if (up ? zq <= pc.z0 : zq >= pc.z0) return pc.t0;
  if (up ? zq >= pc.z1 : zq <= pc.z1) return pc.t1;
  LD t = (a + b) / 2;
  for (int it = 0; it < 200; ++it) {
    const LD f = casteljau(g.z, g.n, t) - zq;
    if (f == 0) return t;
    ((f < 0) == up ? a : b) = t;
    const LD d = casteljau_d(g.z, g.n, t);
    LD next = d != 0 ? t - f / d : (a + b) / 2;
    if (!(next > a && next < b)) next = (a + b) / 2;
    if (std::fabs(next - t) <= 4 * 1.0842e-19L * std::max<LD>(1e-30L, std::fabs(t)) || b - a < 1e-19L)
      return next;
    t = next;
  }
  return t;
}

inline LD g_of(const Seg& g, const Piece& pc, const RayL& ray, LD tau, LD* param) {
  const LD x = ray.o.x + tau * ray.d.x, y = ray.o.y + tau * ray.d.y, z = ray.o.z + tau * ray.d.z;
  const LD t = invert_height(g, pc, z);
  if (param) *param = t;
  const LD r = casteljau(g.r, g.n, t);
  return x * x + y * y - r * r;
}

inline LD bisect(const Seg& g, const Piece& pc, const RayL& ray, LD a, LD b, LD ga) {
  for (int it = 0; it < 200; ++it) {
    const LD m = (a + b) / 2;
    if (!(m > a && m < b)) break;
    const LD gm = g_of(g, pc, ray, m, nullptr);
    if (gm == 0) return m;
    ((gm < 0) == (ga < 0) ? a : b) = m;
  }
  return (a + b) / 2;
}

// Golden-section search for the extremum of g in [a, b] (minimum if sign > 0).
inline LD extremum(const Seg& g, const Piece& pc, const RayL& ray, LD a, LD b, LD sign) {
  const LD k = (std::sqrt(5.0L) - 1) / 2;
  LD x1 = b - k * (b - a), x2 = a + k * (b - a);
  LD f1 = sign * g_of(g, pc, ray, x1, nullptr), f2 = sign * g_of(g, pc, ray, x2, nullptr);
  for (int it = 0; it < 70; ++it) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - k * (b - a), f1 = sign * g_of(g, pc, ray, x1, nullptr);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + k * (b - a), f2 = sign * g_of(g, pc, ray, x2, nullptr);
    }
  }
  return (a + b) / 2;
}

// Ray parameter interval where the ray can meet the piece (cylinder and slab).
inline bool piece_interval(const Piece& pc, const RayL& ray, LD tmin, LD tmax, LD& lo, LD& hi) {
  lo = tmin, hi = tmax;
  const LD A = ray.d.x * ray.d.x + ray.d.y * ray.d.y;
  const LD B = ray.o.x * ray.d.x + ray.o.y * ray.d.y;
  const LD C = ray.o.x * ray.o.x + ray.o.y * ray.o.y;
  const LD R = pc.rbound * (1 + 1e-9L) + 1e-30L;
  if (A > 0) {
    const LD disc = B * B - A * (C - R * R);
    if (disc < 0) return false;
    lo = std::max(lo, (-B - std::sqrt(disc)) / A), hi = std::min(hi, (-B + std::sqrt(disc)) / A);
  } else if (C > R * R) {
    return false;
  }
  const LD za = std::min(pc.z0, pc.z1), zb = std::max(pc.z0, pc.z1);
  if (ray.d.z != 0) {
    LD s1 = (za - ray.o.z) / ray.d.z, s2 = (zb - ray.o.z) / ray.d.z;
    if (s1 > s2) std::swap(s1, s2);
    lo = std::max(lo, s1), hi = std::min(hi, s2);
  } else if (ray.o.z < za || ray.o.z > zb) {
    return false;
  }
  return lo <= hi;
}

struct Root {
  LD tau;
  int piece;
};
struct Event {
  LD tau, g;
};

// g and dg/dtau together: t(z(tau)) has dt/dtau = dz / z'(t), infinite at
// the piece ends.
inline LD g_and_slope(const Seg& g, const Piece& pc, const RayL& ray, LD tau, LD* slope) {
  const LD x = ray.o.x + tau * ray.d.x, y = ray.o.y + tau * ray.d.y, z = ray.o.z + tau * ray.d.z;
  const LD t = invert_height(g, pc, z);
  const LD r = casteljau(g.r, g.n, t), dr = casteljau_d(g.r, g.n, t), dz = casteljau_d(g.z, g.n, t);
  const LD radial = 2 * (x * ray.d.x + y * ray.d.y), num = 2 * r * dr * ray.d.z;
  // z' = 0 exactly at a turning point: its sign is the piece's direction.
  const LD dz_signed = dz != 0 ? dz : (pc.z1 > pc.z0 ? 1e-300L : -1e-300L);
  *slope = num == 0 ? radial : radial - num / dz_signed;
  return x * x + y * y - r * r;
}

// Roots of g in [a, b] where g is monotone (values ga, gb at the ends).
inline void monotone_root(const Seg& g, const Piece& pc, const RayL& ray, LD a, LD b, LD ga, LD gb,
                          int pi, std::vector<Root>& roots) {
  if (ga == 0) roots.push_back({a, pi});
  else if (gb != 0 && (ga < 0) != (gb < 0)) roots.push_back({bisect(g, pc, ray, a, b, ga), pi});
}

struct ScanCtx {
  const Seg& g;
  const Piece& pc;
  const RayL& ray;
  int pi;
  LD s2;
  std::vector<Root>& roots;
  std::vector<Event>& events;
};

// One sample interval. A sign change of g' is an extremum, refined by golden
// section (a touch event, or two close roots). Otherwise the interval is
// halved, 10 times if g changes sign (so a touch next to a root shows up as
// a sign change of g'), up to 24 times if g is small against slope x width
// (it might dip to zero between the samples); a sign change left is a root.
inline void scan_interval(const ScanCtx& c, LD a, LD b, LD ga, LD gb, LD da, LD db, int depth) {
  if ((da > 0 && db < 0) || (da < 0 && db > 0)) {
    const LD te = extremum(c.g, c.pc, c.ray, a, b, da < 0 ? 1 : -1);
    const LD ge = g_of(c.g, c.pc, c.ray, te, nullptr);
    c.events.push_back({te, std::fabs(ge) / c.s2});
    monotone_root(c.g, c.pc, c.ray, a, te, ga, ge, c.pi, c.roots);
    monotone_root(c.g, c.pc, c.ray, te, b, ge, gb, c.pi, c.roots);
    return;
  }
  const bool change = ga == 0 || (gb != 0 && (ga < 0) != (gb < 0));
  const bool small = std::min(std::fabs(ga), std::fabs(gb)) < 2 * (b - a) * std::max(std::fabs(da), std::fabs(db));
  if (change ? depth < 10 : (small && depth < 24)) {
    const LD m = (a + b) / 2;
    LD dm;
    const LD gm = g_and_slope(c.g, c.pc, c.ray, m, &dm);
    scan_interval(c, a, m, ga, gm, da, dm, depth + 1);
    scan_interval(c, m, b, gm, gb, dm, db, depth + 1);
  } else if (change) {
    monotone_root(c.g, c.pc, c.ray, a, b, ga, gb, c.pi, c.roots);
  }
}

// Samples uniform in tau and at uniform profile parameters (dense where the
// height turns), each interval then scanned by scan_interval.
inline void scan_piece(const Profile& p, int pi, const RayL& ray, LD tmin, LD tmax,
                       std::vector<Root>& roots, std::vector<Event>& events) {
  const Piece& pc = p.pieces[pi];
  const Seg& g = p.segs[pc.seg];
  LD lo, hi;
  if (!piece_interval(pc, ray, tmin, tmax, lo, hi)) return;
  const int N = 64;
  std::vector<LD> ts;
  for (int k = 0; k <= N; ++k) ts.push_back(k == N ? hi : lo + (hi - lo) * k / N);
  if (ray.d.z != 0) {
    for (int k = 1; k < 2 * N; ++k) {
      const LD tau = (casteljau(g.z, g.n, pc.t0 + (pc.t1 - pc.t0) * k / (2 * N)) - ray.o.z) / ray.d.z;
      if (tau > lo && tau < hi) ts.push_back(tau);
    }
  }
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
  const size_t M = ts.size();
  std::vector<LD> gs(M), ds(M);
  for (size_t k = 0; k < M; ++k) gs[k] = g_and_slope(g, pc, ray, ts[k], &ds[k]);
  const ScanCtx ctx{g, pc, ray, pi, p.scale * p.scale, roots, events};
  events.push_back({ts[0], std::fabs(gs[0]) / ctx.s2});
  events.push_back({ts[M - 1], std::fabs(gs[M - 1]) / ctx.s2});
  for (size_t k = 0; k + 1 < M; ++k) scan_interval(ctx, ts[k], ts[k + 1], gs[k], gs[k + 1], ds[k], ds[k + 1], 0);
  if (gs[M - 1] == 0) roots.push_back({ts[M - 1], pi});
}

}  // namespace detail

// Nearest hit of the world ray (origin O, unit direction D) with tmin < t < tmax.
inline Result intersect(const Profile& p, const M4& to_local, const glm::dvec3& O,
                        const glm::dvec3& D, LD tmin, LD tmax) {
  detail::RayL ray{to_local.point({O.x, O.y, O.z}), to_local.vec({D.x, D.y, D.z})};
  std::vector<detail::Root> roots;
  std::vector<detail::Event> events;
  for (int pi = 0; pi < int(p.pieces.size()); ++pi) detail::scan_piece(p, pi, ray, tmin, tmax, roots, events);
  Result res;
  const detail::Root* best = nullptr;
  for (const auto& r : roots)
    if (r.tau > tmin && r.tau < tmax && (!best || r.tau < best->tau)) best = &r;
  const LD horizon = best ? best->tau * (1 + 1e-12L) + 1e-12L * p.scale : tmax;
  for (const auto& e : events)
    if (e.tau <= horizon) res.min_event = std::min(res.min_event, e.g);
  if (!best) return res;
  const Piece& pc = p.pieces[best->piece];
  const Seg& g = p.segs[pc.seg];
  LD t;
  detail::g_of(g, pc, ray, best->tau, &t);
  res.found = true, res.t = best->tau, res.seg = pc.seg, res.param = t;
  // Normal = (S_theta x S_t) / r: S(t, th) = (r cos th, r sin th, z), oriented
  // by the sign of r so that it is continuous through the axis.
  const V3 q = ray.o + best->tau * ray.d;
  const LD r = casteljau(g.r, g.n, t), dr = casteljau_d(g.r, g.n, t), dz = casteljau_d(g.z, g.n, t);
  if (std::fabs(r) > 1e-6L * p.scale && std::hypot(dr, dz) > 1e-6L * p.scale) {
    const LD th = r >= 0 ? std::atan2(q.y, q.x) : std::atan2(-q.y, -q.x);
    const V3 st{dr * std::cos(th), dr * std::sin(th), dz}, sth{-r * std::sin(th), r * std::cos(th), 0};
    const V3 n{(sth.y * st.z - sth.z * st.y) / r, (sth.z * st.x - sth.x * st.z) / r,
               (sth.x * st.y - sth.y * st.x) / r};
    res.normal = unit(to_local.vec_transposed(n));
    res.normal_valid = true;
    res.cos = std::fabs(dot(res.normal, V3{D.x, D.y, D.z}));
  }
  return res;
}

}  // namespace bezref
