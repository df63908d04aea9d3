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
  if (n == 0) return c[0];
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

// Root of the polynomial c (degree n) in [lo, hi], where its sign at lo is
// sign_lo and the opposite at hi: Newton, falling back to bisection whenever
// a step leaves the bracket or fails to halve it.
double solve_bracketed(const double* c, int n, double lo, double hi, double sign_lo) {
  double x = 0.5 * (lo + hi);
  double step_before = hi - lo;
  for (int it = 0; it < 200; ++it) {
    double d;
    const double f = bernstein_eval(c, n, x, &d);
    if (f == 0.0) return x;
    if ((f < 0.0) == (sign_lo < 0.0)) lo = x; else hi = x;
    double next = d != 0.0 ? x - f / d : lo;
    const double step = std::fabs(next - x);
    if (!(next > lo && next < hi) || step > 0.5 * step_before) {
      next = 0.5 * (lo + hi);
      step_before = hi - lo;
    } else {
      step_before = step;
    }
    if (hi - lo <= 2.0 * DBL_EPSILON * std::max(1.0, std::fabs(next)) ||
        std::fabs(next - x) <= DBL_EPSILON * std::max(1e-300, std::fabs(x)))
      return next;
    x = next;
  }
  return x;
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
  void emit(double t) {
    if (count_ < kBuffer) roots_[count_++] = std::min(1.0, std::max(0.0, t));
  }
  void monotone(double a, double b, double va, double vb);
  bool unimodal(const Node& nd);
  void process(const Node& nd, Node* stack, int& sp);

  const double* c_;
  int n_;
  double tol_;
  double dc_[kMaxN];
  double roots_[kBuffer];
  int count_ = 0;
};

// At most one root where the polynomial is monotone on [a, b]. A value within
// noise at the ends of [0, 1] also counts (a touching root at the boundary).
void Finder::monotone(double a, double b, double va, double vb) {
  if ((va < 0.0 && vb > 0.0) || (va > 0.0 && vb < 0.0)) {
    emit(solve_bracketed(c_, n_, a, b, va));
  } else if (va == 0.0) {
    emit(a);
  } else if (vb == 0.0) {
    emit(b);
  } else if (a == 0.0 && std::fabs(va) <= tol_ && std::fabs(va) <= std::fabs(vb)) {
    emit(0.0);
  } else if (b == 1.0 && std::fabs(vb) <= tol_ && std::fabs(vb) <= std::fabs(va)) {
    emit(1.0);
  }
}

// One sign change in the derivative's coefficients: split at the extremum.
// Returns false if the derivative's end signs disagree with that (noise).
bool Finder::unimodal(const Node& nd) {
  const double d0 = bernstein_eval(dc_, n_ - 1, nd.u0);
  const double d1 = bernstein_eval(dc_, n_ - 1, nd.u1);
  if (!((d0 < 0.0 && d1 > 0.0) || (d0 > 0.0 && d1 < 0.0))) return false;
  const double te = solve_bracketed(dc_, n_ - 1, nd.u0, nd.u1, d0);
  const double ve = bernstein_eval(c_, n_, te);
  monotone(nd.u0, te, nd.c[0], ve);
  if (std::fabs(ve) <= tol_) emit(te);
  monotone(te, nd.u1, ve, nd.c[n_]);
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
  if (changes == 0) return monotone(nd.u0, nd.u1, c[0], c[n_]);
  if (changes == 1 && unimodal(nd)) return;
  if (lo >= -tol_ && hi <= tol_) {  // indistinguishable from zero here
    int best = 0;
    for (int i = 1; i <= n_; ++i)
      if (std::fabs(c[i]) < std::fabs(c[best])) best = i;
    return emit(nd.u0 + (nd.u1 - nd.u0) * best / n_);
  }
  const double mid = 0.5 * (nd.u0 + nd.u1);
  if (nd.depth >= kMaxDepth || !(mid > nd.u0 && mid < nd.u1)) return emit(mid);
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
    if (c_[0] == 0.0) emit(0.0);
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

// Sort, then merge neighbours that the noise cannot separate.
void Finder::collect(BernsteinRoots& out) const {
  double r[kBuffer];
  std::copy(roots_, roots_ + count_, r);
  std::sort(r, r + count_);
  out.count = 0;
  double last_abs = 0.0;
  for (int i = 0; i < count_; ++i) {
    const double v = std::fabs(bernstein_eval(c_, n_, r[i]));
    if (out.count > 0) {
      const double prev = out.t[out.count - 1];
      if (r[i] - prev <= 4.0 * DBL_EPSILON ||
          std::fabs(bernstein_eval(c_, n_, 0.5 * (prev + r[i]))) <= tol_) {
        if (v < last_abs) {
          out.t[out.count - 1] = r[i];
          last_abs = v;
        }
        continue;
      }
    }
    if (out.count == kMaxBernsteinDegree) break;
    out.t[out.count++] = r[i];
    last_abs = v;
  }
}

}  // namespace

void bernstein_roots(const double* c, int n, double tol, BernsteinRoots& out) {
  Finder finder(c, n, tol);
  finder.run();
  finder.collect(out);
}

}  // namespace ppm
