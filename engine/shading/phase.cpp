// Phase functions: evaluation from the closed forms, sampling by exact inversion where the CDF
// inverts in closed form (HG, Rayleigh) and by a bracketed Newton iteration on the closed-form CDF
// otherwise (Draine, Fournier-Forand), so that every sample follows its density to double
// precision and the returned pdf is the density at the returned angle.
#include "shading/phase.h"

#include <algorithm>
#include <cmath>

namespace ppm {
namespace {

constexpr double kInv4Pi = 1.0 / (4.0 * kPi);
// Cycles' thresholds: below these |g| is isotropic and |alpha| is plain HG.
constexpr double kIsotropicG = 1e-3;
constexpr double kMaxG = 1.0 - 1e-3;
// The smallest sin^2(theta/2) Fournier-Forand samples: 1 - 2 x_min = 1 - 2^-53 is the largest double
// below 1, so the sampled cosine never rounds to 1, where Cycles' FF is 0.
constexpr double kMinFfX = 0x1p-54;

double clamp_unit(double x) { return std::min(1.0, std::max(-1.0, x)); }

// 1 + g^2 - 2 g cos as a sum of non-negative terms: near g = +-1 and cos = +-1 it is (1 -+ g)^2,
// which the plain form loses to cancellation (1e-10 relative at g = 0.999).
double hg_denominator(double cos_theta, double g) {
  const double fac = g >= 0.0 ? (1.0 - g) * (1.0 - g) + 2.0 * g * (1.0 - cos_theta)
                              : (1.0 + g) * (1.0 + g) - 2.0 * g * (1.0 + cos_theta);
  return std::max(1e-300, fac);
}

// Solves cdf(x) = u on [lo, hi] for an increasing cdf with derivative `density`: Newton steps kept
// inside a shrinking bracket, bisection where a step would leave it, so it always converges.
template <class CdfAndDensity>
double invert_cdf(const CdfAndDensity& cdf_and_density, double u, double lo, double hi, double x) {
  for (int i = 0; i < 200 && hi - lo > 1e-15 * (1.0 + std::fabs(lo) + std::fabs(hi)); ++i) {
    double cdf = 0.0, density = 0.0;
    cdf_and_density(x, cdf, density);
    const double r = cdf - u;
    if (r == 0.0) return x;
    (r < 0.0 ? lo : hi) = x;
    double next = x - r / density;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::fabs(next - x) <= 1e-15 * (1.0 + std::fabs(x))) return next;
    x = next;
  }
  return 0.5 * (lo + hi);
}

// P(cos <= mu) of Draine's function. The antiderivative in t = sqrt(1 + g^2 - 2 g mu):
// integral (1 + alpha mu^2) t^-3 dmu = 1/(g t) + alpha/(8 g^3) (2c^2/t + 4c t - 2/3 t^3), c = 1 + g^2.
// It cancels as g^-3 for small g, so there (|g| < 0.1, where the integrand is analytic far beyond
// [-1, 1]) a 16-point Gauss-Legendre rule integrates the density instead, to ~1e-20.
double draine_cdf(double mu, double g, double alpha) {
  const double norm = 1.0 + alpha * (1.0 + 2.0 * g * g) / 3.0;
  if (std::fabs(g) < 0.1) {
    static constexpr double kX[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                                     0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                                     0.9445750230732326, 0.9894009349916499};
    static constexpr double kW[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                                     0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                                     0.0622535239386479, 0.0271524594117541};
    const double half = 0.5 * (mu + 1.0), mid = 0.5 * (mu - 1.0);
    double sum = 0.0;
    for (int i = 0; i < 8; ++i)
      for (const double x : {mid + half * kX[i], mid - half * kX[i]})
        sum += kW[i] * 2.0 * kPi * phase_draine(x, g, alpha);
    return half * sum;
  }
  const double c = 1.0 + g * g;
  const auto antiderivative = [&](double t) {
    return 1.0 / (g * t) + alpha / (8.0 * g * g * g) * (2.0 * c * c / t + 4.0 * c * t - 2.0 / 3.0 * t * t * t);
  };
  const double t = std::sqrt(std::max(0.0, c - 2.0 * g * mu));
  return (1.0 - g * g) / (2.0 * norm) * (antiderivative(t) - antiderivative(1.0 + g));
}

// Fournier-Forand in x = sin^2(theta/2), written with p = delta^-nu (delta = x / x0, x0 = 3 (n-1)^2 / 4)
// so that the forward peak (delta -> 0, delta^nu -> inf as nu < 0) neither overflows nor divides 0 by 0:
//   p(x) = [nu (1-delta) p - p + 1 + (p-1)/x0 - nu (1-delta) p / x] / (4 pi (1-delta)^2)
//          + c180 (3 mu^2 - 1) / (16 pi)
//   F(x) = P(angle below theta) = [p (1-x) + x - delta] / (1 - delta) + c180 mu (1 - mu^2) / 8.
// Both are 0/0 at delta = 1; there the first-order Taylor expansions in eps = 1 - delta are used (the
// density's as Cycles'; for F: 1 + nu (1-x) (1 + (nu+1) eps / 2), whose first-order term Cycles has
// with the opposite sign).
double ff_x0(double n) { return 0.75 * (n - 1.0) * (n - 1.0); }

void ff_cdf_and_density(double x, const FournierForandCoefficients& c, double& cdf, double& density) {
  const double mu = 1.0 - 2.0 * x, eps = 1.0 - x / ff_x0(c.n), nu = c.nu;
  const double p = std::pow(x / ff_x0(c.n), -nu);
  if (std::fabs(eps) < 1e-5)
    cdf = 1.0 + nu * (1.0 - x) * (1.0 + 0.5 * (nu + 1.0) * eps);
  else
    cdf = (p * (1.0 - x) + x - (1.0 - eps)) / eps;
  cdf += c.c180 / 8.0 * mu * (1.0 - mu * mu);
  density = 4.0 * kPi * phase_fournier_forand_at(x, c);  // dF/dx: dmu = -2 dx, and 2 pi around
}

}  // namespace

double phase_henyey_greenstein(double cos_theta, double g) {
  if (!(std::fabs(g) >= kIsotropicG)) return kInv4Pi;
  const double fac = hg_denominator(cos_theta, g);
  return (1.0 - g * g) * kInv4Pi / (fac * std::sqrt(fac));
}

double phase_rayleigh(double cos_theta) { return 3.0 / (16.0 * kPi) * (1.0 + cos_theta * cos_theta); }

double phase_draine(double cos_theta, double g, double alpha) {
  if (std::fabs(g) < kIsotropicG && alpha > 0.999) return phase_rayleigh(cos_theta);
  if (std::fabs(alpha) < 1e-3) return phase_henyey_greenstein(cos_theta, g);
  const double g2 = g * g, fac = hg_denominator(cos_theta, g);
  return (1.0 - g2) * (1.0 + alpha * cos_theta * cos_theta) * kInv4Pi /
         ((1.0 + alpha * (1.0 + 2.0 * g2) / 3.0) * fac * std::sqrt(fac));
}

FournierForandCoefficients fournier_forand_coefficients(double backscatter, double ior) {
  FournierForandCoefficients c;
  c.n = ior;
  const double d90 = 0.5 / ff_x0(ior), d180 = 1.0 / ff_x0(ior);
  // B = (d90^nu - 1) / (2 (1 - d90) d90^nu) solved for nu; its limit -2B where d90 -> 1 (n = 1.816).
  const double log_d90 = std::log(d90);
  c.nu = std::fabs(log_d90) < 1e-9 ? -2.0 * backscatter : -std::log1p(2.0 * backscatter * (d90 - 1.0)) / log_d90;
  c.c180 = std::fabs(d180 - 1.0) < 1e-9 ? -c.nu : (std::pow(d180, -c.nu) - 1.0) / (d180 - 1.0);
  return c;
}

double phase_fournier_forand_at(double x, const FournierForandCoefficients& c) {
  const double mu = 1.0 - 2.0 * x, nu = c.nu, x0 = ff_x0(c.n), eps = 1.0 - x / x0;
  double pf;
  if (std::fabs(eps) < 1e-4) {
    pf = nu * ((nu - 1.0) - (nu + 1.0) / x) / (8.0 * kPi);
    pf += nu * (nu + 1.0) * eps * (2.0 * (nu - 1.0) - (2.0 * nu + 1.0) / x) / (24.0 * kPi);
  } else {
    const double p = std::pow(x / x0, -nu);
    pf = (nu * eps * p - p + 1.0 + (p - 1.0) / x0 - nu * eps * p / x) / (4.0 * kPi * eps * eps);
  }
  return pf + c.c180 / (16.0 * kPi) * (3.0 * mu * mu - 1.0);
}

double phase_fournier_forand(double cos_theta, const FournierForandCoefficients& c) {
  if (!(std::fabs(cos_theta) < 1.0)) return 0.0;  // Cycles' rule (the forward peak is infinite)
  return phase_fournier_forand_at(0.5 * (1.0 - cos_theta), c);
}

double sample_henyey_greenstein_cos(double g, double u) {
  const double mu = 1.0 - 2.0 * u;
  if (!(std::fabs(g) >= kIsotropicG)) return mu;
  // Inverse of F(mu) = (1 - g^2) / (2g) (1 / sqrt(1 + g^2 - 2 g mu) - 1 / (1 + g)).
  const double k = (1.0 - g * g) / (1.0 - g * mu);
  return clamp_unit((1.0 + g * g - k * k) / (2.0 * g));
}

double sample_rayleigh_cos(double u) {
  // F(mu) = (mu^3 + 3 mu + 4) / 8 = u: Cardano's single real root of mu^3 + 3 mu + 2a = 0 is
  // w - 1/w, w = cbrt(sqrt(1 + a^2) - a), written so that neither branch cancels.
  const double a = 2.0 - 4.0 * u, r = std::hypot(1.0, a);
  const double w = a > 0.0 ? 1.0 / std::cbrt(r + a) : std::cbrt(r - a);
  return clamp_unit(w - 1.0 / w);
}

double sample_draine_cos(double g, double alpha, double u) {
  if (std::fabs(g) < kIsotropicG && alpha > 0.999) return sample_rayleigh_cos(u);
  if (std::fabs(alpha) < 1e-3) return sample_henyey_greenstein_cos(g, u);
  const auto f = [&](double mu, double& cdf, double& density) {
    cdf = draine_cdf(mu, g, alpha);
    density = 2.0 * kPi * phase_draine(mu, g, alpha);
  };
  return clamp_unit(invert_cdf(f, u, -1.0, 1.0, sample_henyey_greenstein_cos(g, u)));
}

double sample_fournier_forand_x(const FournierForandCoefficients& c, double u) {
  if (!(c.nu < 0.0)) return kMinFfX;  // B = 0: all of it forward (Cycles' density is 0 there)
  double cdf_min = 0.0, unused = 0.0;
  ff_cdf_and_density(kMinFfX, c, cdf_min, unused);
  if (u <= cdf_min) return kMinFfX;
  // Newton in log x: the density grows as x^-(1+nu) into the forward peak, where x spans 1e-16..1.
  const auto f = [&](double log_x, double& cdf, double& density) {
    const double x = std::exp(log_x);
    ff_cdf_and_density(x, c, cdf, density);
    density *= x;
  };
  const double start = std::log(std::clamp(ff_x0(c.n) * std::pow(u, -1.0 / c.nu), kMinFfX, 1.0));
  return std::clamp(std::exp(invert_cdf(f, u, std::log(kMinFfX), 0.0, start)), kMinFfX, 1.0 - kMinFfX);
}

MieParameters mie_fitted_parameters(double d) {
  d = d > 0.0 ? d : 0.0;  // NaN too
  MieParameters m;
  if (d <= 0.1) {  // eqs. 11-14
    m = {13.8 * d * d, 1.1456 * d * std::sin(9.29044 * d), 250.0, 0.252977 - 312.983 * std::pow(d, 4.3)};
  } else if (d < 1.5) {  // eqs. 15-18
    const double l = std::log(d);
    const double a = (l - 0.238604) * (l + 1.00667), b = 0.507522 - 0.15677 * l;
    const double c = 1.19692 * std::cos(a / b) + 1.37932 * l + 0.0625835;
    m = {0.862 - 0.143 * l * l, 0.379685 * std::cos(c) + 0.344213, 250.0,
         0.146209 * std::cos(3.38707 * l + 2.11193) + 0.316072 + 0.0778917 * l};
  } else if (d < 5.0) {  // eqs. 19-22
    const double l = std::log(d), ll = std::log(l);
    m = {0.0604931 * ll + 0.940256, 0.500411 - 0.081287 / (-2.0 * l + std::tan(l) + 1.27551), 7.30354 * l + 6.31675,
         0.026914 * (l - std::cos(5.68947 * (ll - 0.0292149))) + 0.3764};
  } else if (std::isfinite(d)) {  // eqs. 7-10
    m = {std::exp(-0.0990567 / (d - 1.67154)), std::exp(-2.20679 / (d + 3.91029) - 0.428934),
         std::exp(3.62489 - 8.29288 / (d + 5.52825)), std::exp(-0.599085 / (d - 0.641583) - 0.665888)};
  } else {  // the limit of eqs. 7-10
    m = {1.0, std::exp(-0.428934), std::exp(3.62489), std::exp(-0.665888)};
  }
  return m;
}

double PhaseLobe::eval(double cos_theta) const {
  switch (kind) {
    case PhaseKind::HenyeyGreenstein: return phase_henyey_greenstein(cos_theta, g);
    case PhaseKind::Rayleigh: return phase_rayleigh(cos_theta);
    case PhaseKind::Draine: return phase_draine(cos_theta, g, alpha);
    case PhaseKind::FournierForand: return phase_fournier_forand(cos_theta, ff);
  }
  return 0.0;
}

double PhaseLobe::sample_cos(double u) const {
  switch (kind) {
    case PhaseKind::HenyeyGreenstein: return sample_henyey_greenstein_cos(g, u);
    case PhaseKind::Rayleigh: return sample_rayleigh_cos(u);
    case PhaseKind::Draine: return sample_draine_cos(g, alpha, u);
    case PhaseKind::FournierForand: return 1.0 - 2.0 * sample_fournier_forand_x(ff, u);
  }
  return 1.0;
}

double Phase::eval(double cos_theta) const {
  const double w = second_weight;
  return w > 0.0 ? (1.0 - w) * first.eval(cos_theta) + w * second.eval(cos_theta) : first.eval(cos_theta);
}

PhaseSample Phase::sample(const Vec3& d_in, double u1, double u2) const {
  const double w = second_weight;
  double cos_theta;
  if (w > 0.0 && u1 < w)
    cos_theta = second.sample_cos(u1 / w);
  else
    cos_theta = first.sample_cos(w > 0.0 ? std::min((u1 - w) / (1.0 - w), 1.0 - 0x1p-53) : u1);
  return {direction_around(d_in, cos_theta, u2), eval(cos_theta), cos_theta};
}

Vec3 direction_around(const Vec3& axis, double cos_theta, double u) {
  const double sin_theta = std::sqrt(std::max(0.0, (1.0 - cos_theta) * (1.0 + cos_theta)));
  const double phi = 2.0 * kPi * u;
  Vec3 t, b;
  make_basis(axis, t, b);
  return sin_theta * std::cos(phi) * t + sin_theta * std::sin(phi) * b + cos_theta * axis;
}

namespace {
double clamp_g(double g) {
  if (!(g == g)) return 0.0;
  return std::copysign(std::min(std::fabs(g), kMaxG), g);
}
double clamp_alpha(double alpha) { return alpha > 0.0 ? std::min(alpha, 1e30) : 0.0; }
Phase one_lobe(PhaseKind kind, double g = 0.0, double alpha = 0.0) {
  Phase p;
  p.first.kind = kind;
  p.first.g = clamp_g(g);
  p.first.alpha = clamp_alpha(alpha);
  return p;
}
}  // namespace

Phase henyey_greenstein_phase(double g) { return one_lobe(PhaseKind::HenyeyGreenstein, g); }
Phase rayleigh_phase() { return one_lobe(PhaseKind::Rayleigh); }
Phase draine_phase(double g, double alpha) { return one_lobe(PhaseKind::Draine, g, alpha); }

Phase fournier_forand_phase(double backscatter, double ior) {
  Phase p = one_lobe(PhaseKind::FournierForand);
  const double b = std::fabs(backscatter) < 0.5 - 1e-3 ? std::fabs(backscatter) : 0.5 - 1e-3;  // NaN as 0.499
  const double n = ior > 1.0 + 1e-3 ? std::min(ior, 1e6) : 1.0 + 1e-3;
  p.first.ff = fournier_forand_coefficients(b, n);
  return p;
}

Phase mie_phase(double diameter) {
  const MieParameters m = mie_fitted_parameters(diameter);
  Phase p = one_lobe(PhaseKind::HenyeyGreenstein, m.g_hg);
  p.second = one_lobe(PhaseKind::Draine, m.g_draine, m.alpha).first;
  p.second_weight = std::clamp(m.draine_weight, 0.0, 1.0);
  return p;
}

}  // namespace ppm
