// Tests for the Bernstein root finder and arithmetic: polynomials built in
// long double from known roots (simple, clustered, double, at 0 and 1, none,
// 16 roots) and random polynomials checked against a long-double dense scan.
#include "math/bernstein.h"

#include "math/rng.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace {

using namespace ppm;
using LD = long double;

// Long-double Bernstein coefficients of scale * prod (t - r_k) * extra(t),
// built by multiplying linear factors (independent of the code under test).
std::vector<LD> from_roots(const std::vector<LD>& roots, std::vector<LD> poly = {1.0L}) {
  for (LD r : roots) {
    const int n = int(poly.size()) - 1;
    std::vector<LD> out(n + 2, 0.0L);
    // (t - r) = -r B0 + (1 - r) B1; product weights C(n,i)C(1,j)/C(n+1,i+j).
    for (int i = 0; i <= n; ++i) {
      out[i] += poly[i] * (-r) * LD(n + 1 - i) / LD(n + 1);
      out[i + 1] += poly[i] * (1 - r) * LD(i + 1) / LD(n + 1);
    }
    poly = out;
  }
  return poly;
}

std::vector<double> to_double(const std::vector<LD>& c) { return std::vector<double>(c.begin(), c.end()); }

LD eval_ld(const std::vector<LD>& c, LD t) {
  std::vector<LD> w = c;
  for (size_t k = 1; k < w.size(); ++k)
    for (size_t i = 0; i + k < w.size(); ++i) w[i] = (1 - t) * w[i] + t * w[i + 1];
  return w[0];
}

BernsteinRoots solve(const std::vector<double>& c) {
  BernsteinRoots r;
  const int n = int(c.size()) - 1;
  bernstein_roots(c.data(), n, bernstein_default_tolerance(c.data(), n), r);
  return r;
}

void expect_roots(const std::vector<double>& c, const std::vector<double>& expected, double tol) {
  const BernsteinRoots r = solve(c);
  ASSERT_EQ(r.count, int(expected.size()));
  for (int i = 0; i < r.count; ++i) EXPECT_NEAR(r.t[i], expected[i], tol) << "root " << i;
}

TEST(Bernstein, SimpleRoots) {
  expect_roots(to_double(from_roots({0.1L, 0.35L, 0.6L, 0.9L})), {0.1, 0.35, 0.6, 0.9}, 1e-14);
  // With a positive factor t^2 + 1 (Bernstein 1, 1, 2) and a large scale.
  auto c = from_roots({0.25L, 0.75L}, {1e6L, 1e6L, 2e6L});
  expect_roots(to_double(c), {0.25, 0.75}, 1e-14);
}

// Root of the double-rounded polynomial near `guess`, by long-double bisection.
double refine_ld(const std::vector<double>& c, LD guess, LD half_width) {
  const std::vector<LD> cl(c.begin(), c.end());
  LD a = guess - half_width, b = guess + half_width;
  const LD fa = eval_ld(cl, a);
  for (int it = 0; it < 100; ++it) {
    const LD m = (a + b) / 2;
    ((eval_ld(cl, m) < 0) == (fa < 0) ? a : b) = m;
  }
  return double((a + b) / 2);
}

// Attainable accuracy of a simple root r in double: evaluation error
// (~ eps * sum |c_i| B_i(r)) over the slope |p'(r)|, with a safety factor 16.
double conditioned_tolerance(const std::vector<double>& c, double r) {
  const int n = int(c.size()) - 1;
  std::vector<LD> abs_c, diff;
  for (double v : c) abs_c.push_back(std::fabs(v));
  for (int i = 0; i < n; ++i) diff.push_back(LD(n) * (LD(c[i + 1]) - LD(c[i])));
  return double(16 * 2.2e-16L * eval_ld(abs_c, r) / std::fabs(eval_ld(diff, r))) + 1e-15;
}

void expect_conditioned(const std::vector<double>& c, const std::vector<double>& ref) {
  const BernsteinRoots r = solve(c);
  ASSERT_EQ(r.count, int(ref.size()));
  for (int i = 0; i < r.count; ++i) {
    EXPECT_NEAR(r.t[i], ref[i], conditioned_tolerance(c, ref[i])) << "root " << i;
    EXPECT_FALSE(r.multiple[i]);
  }
}

TEST(Bernstein, ClusteredRoots) {
  // Rounding the coefficients to double moves roots 1e-4 apart by ~1e-10:
  // compare with the nominal roots loosely, and with the roots of the rounded
  // polynomial (long double) within the accuracy double evaluation allows.
  const auto c1 = to_double(from_roots({0.5L, 0.5001L, 0.5002L}));
  expect_roots(c1, {0.5, 0.5001, 0.5002}, 1e-9);
  expect_conditioned(c1, {refine_ld(c1, 0.5L, 4e-5L), refine_ld(c1, 0.5001L, 4e-5L), refine_ld(c1, 0.5002L, 4e-5L)});
  const auto c2 = to_double(from_roots({0.3L, 0.30001L, 0.8L}));
  expect_roots(c2, {0.3, 0.30001, 0.8}, 1e-9);
  expect_conditioned(c2, {refine_ld(c2, 0.3L, 4e-6L), refine_ld(c2, 0.30001L, 4e-6L), refine_ld(c2, 0.8L, 1e-3L)});
}

TEST(Bernstein, DoubleRoots) {
  // Even multiplicity: no sign change; reported once, to ~sqrt(eps).
  expect_roots(to_double(from_roots({0.3L, 0.3L, 0.7L})), {0.3, 0.7}, 1e-7);
  expect_roots(to_double(from_roots({0.45L, 0.45L}, {1.0L, 1.0L, 2.0L})), {0.45}, 1e-7);
  expect_roots(to_double(from_roots({1.0L / 3, 1.0L / 3, 0.9L, 0.9L})), {1.0 / 3, 0.9}, 1e-7);
  // Exactly representable double root: exact answer, flagged as multiple.
  expect_roots({0.25, -0.25, 0.25}, {0.5}, 0.0);
  const std::vector<double> sq = {0.25, -0.25, 0.25};
  EXPECT_TRUE(solve(sq).multiple[0]);
}

TEST(Bernstein, RootsAtTheEnds) {
  expect_roots(to_double(from_roots({0.0L, 0.5L, 1.0L})), {0.0, 0.5, 1.0}, 1e-15);
  expect_roots(to_double(from_roots({0.0L, 0.0L, 0.6L})), {0.0, 0.6}, 1e-15);
  expect_roots(to_double(from_roots({1.0L, 1.0L, 0.2L})), {0.2, 1.0}, 1e-15);
}

TEST(Bernstein, NoRoots) {
  expect_roots(to_double(from_roots({-0.5L, 1.5L})), {}, 0.0);
  expect_roots(to_double(from_roots({-1e-3L, 1.001L})), {}, 0.0);  // just outside [0, 1]
  // (t - 0.5)^2 + 1e-6: a near-miss well above the noise.
  auto c = from_roots({0.5L, 0.5L});
  for (auto& v : c) v += 1e-6L;
  expect_roots(to_double(c), {}, 0.0);
  expect_roots({1.0, 2.0, 3.0, 4.0}, {}, 0.0);
}

TEST(Bernstein, SixteenRoots) {
  std::vector<LD> roots;
  std::vector<double> expected;
  for (int k = 0; k < 16; ++k) {
    const LD r = 0.5L - 0.5L * std::cos((2 * k + 1) * 3.14159265358979323846264L / 32);
    roots.push_back(r);
    expected.push_back(double(r));
  }
  expect_roots(to_double(from_roots(roots)), expected, 1e-10);
}

// Independent reference: dense long-double sign scan plus bisection.
std::vector<LD> reference_roots(const std::vector<LD>& c, bool& near_double) {
  std::vector<LD> out;
  const int N = 8000;
  LD scale = 0;
  for (LD v : c) scale = std::max(scale, std::fabs(v));
  LD prev = eval_ld(c, 0), prev2 = prev;
  near_double = false;
  if (prev == 0) out.push_back(0);
  for (int k = 1; k <= N; ++k) {
    const LD t = LD(k) / N, cur = eval_ld(c, t);
    if (cur != 0 && prev != 0 && (cur < 0) != (prev < 0)) {
      LD a = LD(k - 1) / N, b = t;
      for (int it = 0; it < 100; ++it) {
        const LD m = (a + b) / 2, v = eval_ld(c, m);
        ((v < 0) == (prev < 0) ? a : b) = m;
      }
      out.push_back((a + b) / 2);
    } else if (cur == 0) {
      out.push_back(t);
    }
    // A local extremum of |p| close to zero: ambiguous, skip the polynomial.
    if (k >= 2 && std::fabs(prev) < std::fabs(prev2) && std::fabs(prev) < std::fabs(cur) &&
        (prev < 0) == (cur < 0) && (prev < 0) == (prev2 < 0) && std::fabs(prev) < 1e-9L * scale)
      near_double = true;
    prev2 = prev, prev = cur;
  }
  return out;
}

TEST(Bernstein, RandomPolynomialsMatchLongDoubleScan) {
  Rng rng(3, 1, 0);
  int checked = 0, total_roots = 0;
  const int trials = test_samples(400);
  for (int trial = 0; trial < trials; ++trial) {
    const int n = 1 + trial % 16;
    std::vector<double> c(n + 1);
    for (auto& v : c) v = 2 * rng.uniform() - 1;
    bool near_double;
    const std::vector<LD> ref = reference_roots(std::vector<LD>(c.begin(), c.end()), near_double);
    if (near_double) continue;
    ++checked;
    total_roots += int(ref.size());
    const BernsteinRoots r = solve(c);
    ASSERT_EQ(r.count, int(ref.size())) << "trial " << trial;
    for (int i = 0; i < r.count; ++i) EXPECT_NEAR(r.t[i], double(ref[i]), 1e-10) << "trial " << trial;
  }
  EXPECT_GT(checked, trials * 37 / 40);  // few are too close to a double root to decide
  EXPECT_GT(total_roots, trials / 2);
}

TEST(Bernstein, ArithmeticMatchesLongDouble) {
  Rng rng(5, 2, 0);
  for (int trial = 0; trial < 50; ++trial) {
    const int na = 1 + trial % 8, nb = 1 + (trial / 8) % 8;
    std::vector<double> a(na + 1), b(nb + 1), prod(na + nb + 1), el(16 + 1), left(na + 1), right(na + 1);
    for (auto& v : a) v = 2 * rng.uniform() - 1;
    for (auto& v : b) v = 2 * rng.uniform() - 1;
    bernstein_multiply(a.data(), na, b.data(), nb, prod.data());
    bernstein_elevate(a.data(), na, 16, el.data());
    const double ts = rng.uniform();
    bernstein_split(a.data(), na, ts, left.data(), right.data());
    const std::vector<LD> al(a.begin(), a.end()), bl(b.begin(), b.end());
    for (double t : {0.0, 0.13, 0.5, 0.77, 1.0}) {
      const LD pa = eval_ld(al, t), pb = eval_ld(bl, t);
      double d;
      EXPECT_NEAR(bernstein_eval(a.data(), na, t, &d), double(pa), 1e-14);
      EXPECT_NEAR(bernstein_eval(prod.data(), na + nb, t), double(pa * pb), 1e-14);
      EXPECT_NEAR(bernstein_eval(el.data(), 16, t), double(pa), 1e-14);
      EXPECT_NEAR(bernstein_eval(left.data(), na, t), double(eval_ld(al, t * ts)), 1e-14);
      EXPECT_NEAR(bernstein_eval(right.data(), na, t), double(eval_ld(al, ts + t * (1 - ts))), 1e-14);
      const LD h = 1e-6L;
      EXPECT_NEAR(d, double((eval_ld(al, t + h) - eval_ld(al, t - h)) / (2 * h)), 1e-6);
    }
  }
}

}  // namespace
