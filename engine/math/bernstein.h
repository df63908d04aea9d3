// Polynomials in the Bernstein basis on [0, 1] (degree <= 16): evaluation,
// products, degree elevation, subdivision and a root finder that cannot skip a
// root. The finder subdivides with de Casteljau, discards intervals whose
// coefficients all share one sign (convex hull), solves intervals where the
// polynomial is monotone (no sign change among the derivative's coefficients)
// by bracketed Newton, and splits unimodal intervals (one sign change) where
// the polynomial is clearly past zero or else at its extremum, so that roots
// of even multiplicity (no sign change: a ray touching a surface) are reported
// when the extremum lies within the caller's noise bound. Fixed-size arrays
// only: nothing allocates. Work is capped at 4096 intervals (reached only by
// polynomials that are noise over a wide range).
#pragma once

namespace ppm {

constexpr int kMaxBernsteinDegree = 16;

// Value of sum_i c[i] * B_{i,n}(t). O(n); also fine slightly outside [0, 1].
double bernstein_eval(const double* c, int n, double t);
// Value, with the first derivative written to *derivative.
double bernstein_eval(const double* c, int n, double t, double* derivative);

// out (degree na + nb) = a (degree na) * b (degree nb); na + nb <= 16.
void bernstein_multiply(const double* a, int na, const double* b, int nb, double* out);
// The same polynomial written with degree m >= n.
void bernstein_elevate(const double* c, int n, int m, double* out);
// Derivative (degree n - 1, factor n included); n >= 1.
void bernstein_derivative(const double* c, int n, double* out);
// Coefficients of the pieces on [0, t] and [t, 1] (de Casteljau).
void bernstein_split(const double* c, int n, double t, double* left, double* right);

// A noise bound fit for coefficients that are exact up to a few roundings:
// 32 * (n + 1) * machine epsilon * max |c_i|.
double bernstein_default_tolerance(const double* c, int n);

struct BernsteinRoots {
  int count = 0;
  double t[kMaxBernsteinDegree];      // ascending, in [0, 1]
  bool multiple[kMaxBernsteinDegree];  // no sign change resolvable within tol:
                                       // a touching root or a merged cluster
};

// All roots of the polynomial in [0, 1] (n <= 16). `tol` bounds the absolute
// error of the coefficients: an interval whose coefficients all exceed tol in
// one sign holds no root, and a local extremum with |value| <= tol is a
// (double) root, reported at the extremum. Roots that the noise cannot
// separate (|p| <= tol midway, closer than 1e-3) are reported once, flagged
// multiple. Simple roots are accurate to about the rounding of p over |p'|.
void bernstein_roots(const double* c, int n, double tol, BernsteinRoots& out);

}  // namespace ppm
