// The old design (student report), kept only as a foil for the tests and the
// benchmark: the ray/surface condition written with a division by the ray's
// axis component dz, expanded to a power-basis polynomial of degree 2n in the
// profile parameter, and solved by Newton from the fixed starts 0, 1/4, 1/2,
// 3/4, 1. It misses roots that no start converges to and fails outright when
// dz = 0. Do not use it for rendering.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <vector>

namespace bezfoil {

struct Foil {
  struct Seg {
    int n;
    double r[9], z[9];  // power-basis coefficients
  };
  std::vector<Seg> segs;
  glm::dmat4 to_local;
};

// Bernstein control values -> power-basis coefficients.
inline void to_power(const double* c, int n, double* out) {
  auto binom = [](int a, int b) {
    double v = 1;
    for (int i = 1; i <= b; ++i) v = v * (a - b + i) / i;
    return v;
  };
  for (int k = 0; k <= n; ++k) {
    out[k] = 0;
    for (int i = 0; i <= k; ++i)
      out[k] += c[i] * binom(n, i) * binom(n - i, k - i) * ((k - i) % 2 ? -1.0 : 1.0);
  }
}

inline Foil make(const std::vector<glm::dvec2>& pts, bool chain, const glm::dmat4& to_world) {
  Foil f;
  f.to_local = glm::inverse(to_world);
  const int n = chain ? 3 : int(pts.size()) - 1;
  for (size_t s = 0; s + n < pts.size(); s += n) {
    Foil::Seg g;
    g.n = n;
    double r[9], z[9];
    for (int i = 0; i <= n; ++i) r[i] = pts[s + i].x, z[i] = pts[s + i].y;
    to_power(r, n, g.r);
    to_power(z, n, g.z);
    f.segs.push_back(g);
  }
  return f;
}

inline double horner(const double* c, int n, double t, double* d) {
  double v = c[n], dv = 0;
  for (int i = n - 1; i >= 0; --i) dv = dv * t + v, v = v * t + c[i];
  *d = dv;
  return v;
}

inline void square_add(const double* a, int n, double* out) {
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) out[i + j] += a[i] * a[j];
}

// Nearest hit distance in (tmin, tmax), or false.
inline bool intersect(const Foil& f, const glm::dvec3& O, const glm::dvec3& D, double tmin,
                      double tmax, double& t_out) {
  const glm::dvec3 o = glm::dvec3(f.to_local * glm::dvec4(O, 1.0));
  const glm::dvec3 d = glm::dmat3(f.to_local) * D;  // parameter = world distance
  bool found = false;
  t_out = tmax;
  for (const auto& g : f.segs) {
    const int n = g.n;
    double x[9], y[9], p[17] = {};
    for (int i = 0; i <= n; ++i) x[i] = d.x / d.z * g.z[i], y[i] = d.y / d.z * g.z[i];
    x[0] += o.x - d.x / d.z * o.z;
    y[0] += o.y - d.y / d.z * o.z;
    square_add(x, n, p);
    square_add(y, n, p);
    double r2[17] = {};
    square_add(g.r, n, r2);
    for (int i = 0; i <= 2 * n; ++i) p[i] -= r2[i];
    for (double t0 : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      double t = t0;
      bool ok = false;
      for (int it = 0; it < 30 && !ok; ++it) {
        double dp;
        const double v = horner(p, 2 * n, t, &dp);
        const double step = v / dp;
        t -= step;
        ok = std::fabs(step) < 1e-12;
      }
      if (!ok || !(t >= 0.0 && t <= 1.0)) continue;
      double dz;
      const double s = (horner(g.z, n, t, &dz) - o.z) / d.z;
      if (s > tmin && s < t_out) t_out = s, found = true;
    }
  }
  return found;
}

}  // namespace bezfoil
