// Bernstein-basis polynomial arithmetic and the subdivision root finder
// described in bernstein.h.
#include "math/bernstein.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace ppm {

namespace {

constexpr int kMaxN = kMaxBernsteinDegree;

struct BinomialTable {
  double v[kMaxN + 1][kMaxN + 1];
  constexpr BinomialTable() : v() {
    for (int n = 0; n <= kMaxN; ++n) {
      v[n][0] = 1.0;
      for (int k = 1; k <= n; ++k) v[n][k] = v[n - 1][k - 1] + (k < n ? v[n - 1][k] : 0.0);
    }
  }
};
constexpr BinomialTable kBinom{};

inline double ipow(double x, int n) {
  double r = 1.0;
  for (int i = 0; i < n; ++i) r *= x;
  return r;
}

}  // namespace

// Horner on t/(1-t) (or (1-t)/t past the middle) keeps every power <= 1, so
// the error stays of order n * eps * sum |c_i| B_i(t), like de Casteljau's.
double bernstein_eval(const double* c, int n, double t) {
  if (n == 0 || t == 0.0) return c[0];
  if (t == 1.0) return c[n];
  const double* b = kBinom.v[n];
  const double u = 1.0 - t;
  if (t <= 0.5) {
    const double s = t / u;
    double acc = c[n];
    for (int i = n - 1; i >= 0; --i) acc = acc * s + c[i] * b[i];
    return acc * ipow(u, n);
  }
  const double s = u / t;
  double acc = c[0];
  for (int i = 1; i <= n; ++i) acc = acc * s + c[i] * b[i];
  return acc * ipow(t, n);
}

double bernstein_eval(const double* c, int n, double t, double* derivative) {
  if (n == 0) {
    *derivative = 0.0;
    return c[0];
  }
  if (t == 0.0 || t == 1.0) {  // exact at the ends
    *derivative = t == 0.0 ? n * (c[1] - c[0]) : n * (c[n] - c[n - 1]);
    return t == 0.0 ? c[0] : c[n];
  }
  const double* b = kBinom.v[n];
  const double* bd = kBinom.v[n - 1];
  const double u = 1.0 - t;
  double acc, dacc, scale, last;
  if (t <= 0.5) {
    const double s = t / u;
    acc = c[n];
    dacc = c[n] - c[n - 1];
    for (int i = n - 1; i >= 0; --i) {
      acc = acc * s + c[i] * b[i];
      if (i < n - 1) dacc = dacc * s + (c[i + 1] - c[i]) * bd[i];
    }
    scale = ipow(u, n - 1);
    last = u;
  } else {
    const double s = u / t;
    acc = c[0];
    dacc = c[1] - c[0];
    for (int i = 1; i <= n; ++i) {
      acc = acc * s + c[i] * b[i];
      if (i < n) dacc = dacc * s + (c[i + 1] - c[i]) * bd[i];
    }
    scale = ipow(t, n - 1);
    last = t;
  }
  *derivative = n * dacc * scale;
  return acc * scale * last;
}

void bernstein_multiply(const double* a, int na, const double* b, int nb, double* out) {
  const int n = na + nb;
  double tmp[kMaxN + 1] = {};
  for (int i = 0; i <= na; ++i) {
    const double ai = a[i] * kBinom.v[na][i];
    for (int j = 0; j <= nb; ++j) tmp[i + j] += ai * b[j] * kBinom.v[nb][j];
  }
  for (int k = 0; k <= n; ++k) out[k] = tmp[k] / kBinom.v[n][k];
}

void bernstein_elevate(const double* c, int n, int m, double* out) {
  double ones[kMaxN + 1];
  std::fill(ones, ones + kMaxN + 1, 1.0);
  bernstein_multiply(c, n, ones, m - n, out);
}

void bernstein_derivative(const double* c, int n, double* out) {
  for (int i = 0; i < n; ++i) out[i] = n * (c[i + 1] - c[i]);
}

void bernstein_split(const double* c, int n, double t, double* left, double* right) {
  double w[kMaxN + 1];
  std::copy(c, c + n + 1, w);
  const double u = 1.0 - t;
  left[0] = w[0];
  right[n] = w[n];
  for (int k = 1; k <= n; ++k) {
    for (int i = 0; i <= n - k; ++i) w[i] = u * w[i] + t * w[i + 1];
    left[k] = w[0];
    right[n - k] = w[n - k];
  }
}

double bernstein_default_tolerance(const double* c, int n) {
  double m = 0.0;
  for (int i = 0; i <= n; ++i) m = std::max(m, std::fabs(c[i]));
  return 32.0 * (n + 1) * DBL_EPSILON * m;
}

namespace {

// Root of the polynomial c (degree n) in [lo, hi], given its sign at lo (the
// opposite at hi) and a first guess: Newton, falling back to bisection whenever
// a step leaves the bracket or fails to halve the previous one. A Newton step
// of 1e-12 leaves an error of order its square (over the distance to the next
// root), below the rounding of f: stop there. After a step below 1e-6, one
// pointing outside the bracket is rounding noise, not a reason to bisect.
double solve_bracketed(const double* c, int n, double lo, double hi, double sign_lo, double guess) {
  double x = guess > lo && guess < hi ? guess : 0.5 * (lo + hi);
  double step_before = hi - lo;
  for (int it = 0; it < 200; ++it) {
    double d;
    const double f = bernstein_eval(c, n, x, &d);
    if (f == 0.0) return x;
    if ((f < 0.0) == (sign_lo < 0.0)) lo = x; else hi = x;
    double next = d != 0.0 ? x - f / d : lo;
    const double step = std::fabs(next - x);
    const bool inside = next > lo && next < hi;
    if (inside && step <= 0.5 * step_before) {
      if (step <= 1e-12) return next;
      step_before = step;
    } else {
      if (!inside && step_before <= 1e-6) return x;
      next = 0.5 * (lo + hi);
      step_before = hi - lo;
    }
    if (hi - lo <= 2.0 * DBL_EPSILON) return next;
    x = next;
  }
  return x;
}

// Where the control polygon of coefficients c on [a, b] first crosses zero:
// close to the root of a monotone piece (it converges quadratically with
// subdivision), so Newton starts near it.
double polygon_crossing(const double* c, int n, double a, double b) {
  for (int i = 0; i < n; ++i)
    if ((c[i] < 0.0) != (c[i + 1] < 0.0)) return a + (b - a) * (i + c[i] / (c[i] - c[i + 1])) / n;
  return 0.5 * (a + b);
}

struct Node {
  double u0, u1;
  int depth;
  double c[kMaxN + 1];
};

constexpr int kMaxDepth = 48;      // width 2^-48: far below any useful root separation
constexpr int kMaxVisits = 4096;   // bound on work for pathological (all-noise) input
constexpr int kBuffer = 2 * kMaxN + 8;

// Working state of one bernstein_roots call (on the stack).
class Finder {
 public:
  Finder(const double* c, int n, double tol) : c_(c), n_(n), tol_(tol) {
    if (n > 0) bernstein_derivative(c, n, dc_);
  }
  void run();
  void collect(BernsteinRoots& out) const;

 private:
  void emit(double t, bool multiple) {
    if (count_ < kBuffer) roots_[count_++] = {std::min(1.0, std::max(0.0, t)), multiple};
  }
  void monotone(double a, double b, const double* c, double va, double vb);
  bool unimodal(const Node& nd);
  void process(const Node& nd, Node* stack, int& sp);

  const double* c_;
  int n_;
  double tol_;
  double dc_[kMaxN];
  struct Emitted {
    double t;
    bool multiple;
  };
  Emitted roots_[kBuffer];
  int count_ = 0;
};

// At most one root where the polynomial is monotone on [a, b] (coefficients
// c there, end values va and vb). A value within noise at the ends of [0, 1]
// also counts (a touching root at the boundary).
void Finder::monotone(double a, double b, const double* c, double va, double vb) {
  if ((va < 0.0 && vb > 0.0) || (va > 0.0 && vb < 0.0)) {
    emit(solve_bracketed(c_, n_, a, b, va, polygon_crossing(c, n_, a, b)), false);
  } else if (va == 0.0) {
    emit(a, false);
  } else if (vb == 0.0) {
    emit(b, false);
  } else if (a == 0.0 && std::fabs(va) <= tol_ && std::fabs(va) <= std::fabs(vb)) {
    emit(0.0, true);
  } else if (b == 1.0 && std::fabs(vb) <= tol_ && std::fabs(vb) <= std::fabs(va)) {
    emit(1.0, true);
  }
}

// One sign change in the derivative's coefficients: p falls then rises (or
// the reverse). Split where p is clearly past zero on the extremum's side (at
// first try the extreme control point: one evaluation), else at the extremum
// itself, whose value decides a touching root. Each side holds at most one
// root. Returns false if the derivative's end signs disagree (noise).
bool Finder::unimodal(const Node& nd) {
  const double d0 = bernstein_eval(dc_, n_ - 1, nd.u0);
  const double d1 = bernstein_eval(dc_, n_ - 1, nd.u1);
  if (!((d0 < 0.0 && d1 > 0.0) || (d0 > 0.0 && d1 < 0.0))) return false;
  const double side = d0 < 0.0 ? -1.0 : 1.0;  // -1: a minimum
  int ie = 0;
  for (int i = 1; i <= n_; ++i)
    if (side * nd.c[i] > side * nd.c[ie]) ie = i;
  double split = nd.u0 + (nd.u1 - nd.u0) * ie / n_;
  double vs = bernstein_eval(c_, n_, split);
  bool touching = false;
  if (!(ie > 0 && ie < n_ && side * vs > tol_)) {
    double dn[kMaxN];
    for (int i = 0; i < n_; ++i) dn[i] = nd.c[i + 1] - nd.c[i];
    split = solve_bracketed(dc_, n_ - 1, nd.u0, nd.u1, d0, polygon_crossing(dn, n_ - 1, nd.u0, nd.u1));
    vs = bernstein_eval(c_, n_, split);
    touching = std::fabs(vs) <= tol_;
  }
  double left[kMaxN + 1], right[kMaxN + 1];
  bernstein_split(nd.c, n_, (split - nd.u0) / (nd.u1 - nd.u0), left, right);
  monotone(nd.u0, split, left, nd.c[0], vs);
  if (touching) emit(split, true);
  monotone(split, nd.u1, right, vs, nd.c[n_]);
  return true;
}

void Finder::process(const Node& nd, Node* stack, int& sp) {
  const double* c = nd.c;
  double lo = c[0], hi = c[0];
  for (int i = 1; i <= n_; ++i) {
    lo = std::min(lo, c[i]);
    hi = std::max(hi, c[i]);
  }
  if (lo > tol_ || hi < -tol_) return;  // one sign beyond noise: no root
  int changes = 0, last = 0;  // sign changes of the derivative's coefficients
  for (int i = 0; i < n_; ++i) {
    const double d = c[i + 1] - c[i];
    const int s = d > 0.0 ? 1 : (d < 0.0 ? -1 : 0);
    if (s != 0 && last != 0 && s != last) ++changes;
    if (s != 0) last = s;
  }
  if (changes == 0) return monotone(nd.u0, nd.u1, c, c[0], c[n_]);
  if (changes == 1 && unimodal(nd)) return;
  if (lo >= -tol_ && hi <= tol_) {  // indistinguishable from zero here
    int best = 0;
    for (int i = 1; i <= n_; ++i)
      if (std::fabs(c[i]) < std::fabs(c[best])) best = i;
    return emit(nd.u0 + (nd.u1 - nd.u0) * best / n_, true);
  }
  const double mid = 0.5 * (nd.u0 + nd.u1);
  if (nd.depth >= kMaxDepth || !(mid > nd.u0 && mid < nd.u1)) return emit(mid, true);
  Node& right = stack[sp++];
  Node& left = stack[sp++];
  right.u0 = left.u1 = mid;
  right.u1 = nd.u1;
  left.u0 = nd.u0;
  right.depth = left.depth = nd.depth + 1;
  bernstein_split(c, n_, 0.5, left.c, right.c);
}

void Finder::run() {
  if (n_ == 0) {
    if (c_[0] == 0.0) emit(0.0, true);
    return;
  }
  Node stack[kMaxDepth + 3];
  int sp = 1;
  stack[0].u0 = 0.0;
  stack[0].u1 = 1.0;
  stack[0].depth = 0;
  std::copy(c_, c_ + n_ + 1, stack[0].c);
  for (int visits = 0; sp > 0 && visits < kMaxVisits; ++visits) {
    const Node nd = stack[--sp];  // copy: process() may overwrite this slot
    process(nd, stack, sp);
  }
}

// Sort, then merge neighbours that the noise cannot separate: |p| <= tol
// midway. Only neighbours closer than 1e-3 are examined: farther apart, a
// polynomial within noise between them is flat noise (reported once anyway
// by the all-noise rule of process()).
void Finder::collect(BernsteinRoots& out) const {
  Emitted r[kBuffer];
  std::copy(roots_, roots_ + count_, r);
  std::sort(r, r + count_, [](const Emitted& x, const Emitted& y) { return x.t < y.t; });
  out.count = 0;
  for (int i = 0; i < count_; ++i) {
    if (out.count > 0) {
      const int k = out.count - 1;
      const double gap = r[i].t - out.t[k];
      if (gap <= 4.0 * DBL_EPSILON ||
          (gap < 1e-3 && std::fabs(bernstein_eval(c_, n_, 0.5 * (out.t[k] + r[i].t))) <= tol_)) {
        // Prefer an extremum (well conditioned) over a bracketed root beside it.
        const bool take = r[i].multiple != out.multiple[k]
                              ? r[i].multiple
                              : std::fabs(bernstein_eval(c_, n_, r[i].t)) < std::fabs(bernstein_eval(c_, n_, out.t[k]));
        out.multiple[k] = out.multiple[k] || r[i].multiple || gap > 0.0;
        if (take) out.t[k] = r[i].t;
        continue;
      }
    }
    if (out.count == kMaxBernsteinDegree) break;
    out.t[out.count] = r[i].t;
    out.multiple[out.count++] = r[i].multiple;
  }
}

}  // namespace

void bernstein_roots(const double* c, int n, double tol, BernsteinRoots& out) {
  out.count = 0;
  double lo = c[0], hi = c[0];  // the common case of a ray miss: exit at once
  for (int i = 1; i <= n; ++i) lo = std::min(lo, c[i]), hi = std::max(hi, c[i]);
  if (lo > tol || hi < -tol) return;
  Finder finder(c, n, tol);
  finder.run();
  finder.collect(out);
}

}  // namespace ppm
