// Phase functions (shading/phase.h): each integrates to 1 over the sphere; its samples follow its
// density (a chi-square over bins of the angle, the expected counts by quadrature of eval, not by
// the sampler's CDF); the returned pdf is eval; values agree with the papers' formulas evaluated
// again here in long double; Cycles' clamps and special cases hold; extreme parameters stay finite.
#include "math/rng.h"
#include "shading/phase.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

namespace ppm {
namespace {

using Density = std::function<double(double x)>;  // density per steradian at x = sin^2(theta/2)

// Fournier-Forand at x itself: its forward peak holds mass where 1 - 2x rounds to 1.
Density of(const Phase& p) {
  if (p.first.kind == PhaseKind::FournierForand)
    return [p](double x) { return phase_fournier_forand_at(x, p.first.ff); };
  return [p](double x) { return p.eval(1.0 - 2.0 * x); };
}

// Integral of 2 pi p over cos theta, i.e. of 4 pi p over x, for z in [za, zb] within one half:
// x = z (the forward half) or x = 1 - z (the back half). Simpson's rule in log z, so that peaks at
// either pole are resolved.
double integrate_half(const Density& f, double za, double zb, bool back) {
  const auto g = [&](double y) {
    const double z = std::exp(y);
    return 4.0 * kPi * f(back ? 1.0 - z : z) * z;
  };
  const double ya = std::log(za), yb = std::log(zb);
  const int n = 2 * std::max(100, int(100.0 * (yb - ya)));  // steps of at most 0.005 in log z
  const double h = (yb - ya) / n;
  double sum = g(ya) + g(yb);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * g(ya + i * h);
  return sum * h / 3.0;
}

// The probability of x in [a, b] (0 <= a < b <= 1); within 1e-300 of either pole it is left out
// (the Fournier-Forand tests add its closed-form forward tail).
double probability(const Density& f, double a, double b) {
  double sum = 0.0;
  if (a < 0.5) sum += integrate_half(f, std::max(a, 1e-300), std::min(b, 0.5), false);
  if (b > 0.5) sum += integrate_half(f, std::max(1.0 - b, 1e-300), std::min(1.0 - a, 0.5), true);
  return sum;
}

// Bin edges in x: log-spaced towards both poles, where peaked functions put their mass.
std::vector<double> bin_edges() {
  std::vector<double> e{0.0};
  for (int k = 28; k >= 1; --k) e.push_back(0.5 * std::pow(10.0, -k / 4.0));
  const double last_log = 0.5 * std::pow(10.0, -0.25);
  for (int k = 1; k <= 9; ++k) e.push_back(last_log + k * (0.5 - last_log) / 10.0);
  const size_t half = e.size();
  e.push_back(0.5);
  for (size_t i = half; i-- > 1;) e.push_back(1.0 - e[i]);
  e.push_back(1.0);
  return e;
}

struct ChiSquare {
  double value = 0.0;
  int dof = 0;
};

// Samples `p` n times from a fixed direction and compares the histogram of x with the quadrature
// of eval; bins expecting fewer than 20 are lumped into one. Also checks each sample's own record.
ChiSquare sample_chi_square(const Phase& p, int n, uint64_t seed) {
  const std::vector<double> edges = bin_edges();
  std::vector<double> counts(edges.size() - 1, 0.0);
  Rng rng(seed, 11, 0);
  const Vec3 d_in = glm::normalize(Vec3(0.3, -0.5, 0.8));
  for (int i = 0; i < n; ++i) {
    const PhaseSample s = p.sample(d_in, rng.uniform(), rng.uniform());
    EXPECT_EQ(s.pdf, p.eval(s.cos_theta));
    EXPECT_NEAR(glm::length(s.direction), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(s.direction, d_in), s.cos_theta, 1e-12);
    const double x = 0.5 * (1.0 - s.cos_theta);
    const size_t bin = std::upper_bound(edges.begin(), edges.end(), x) - edges.begin() - 1;
    counts[std::min(bin, counts.size() - 1)] += 1.0;
  }
  ChiSquare chi;
  double lumped_expected = 0.0, lumped_count = 0.0;
  for (size_t i = 0; i + 1 < edges.size(); ++i) {
    const double expected = n * probability(of(p), edges[i], edges[i + 1]);
    if (expected < 20.0) {
      lumped_expected += expected;
      lumped_count += counts[i];
      continue;
    }
    chi.value += (counts[i] - expected) * (counts[i] - expected) / expected;
    ++chi.dof;
  }
  if (lumped_expected > 0.0)
    chi.value += (lumped_count - lumped_expected) * (lumped_count - lumped_expected) / lumped_expected;
  return chi;
}

struct Named {
  const char* name;
  Phase phase;
};

std::vector<Named> phases() {
  return {{"HG g=0", henyey_greenstein_phase(0.0)},
          {"HG g=0.5", henyey_greenstein_phase(0.5)},
          {"HG g=-0.7", henyey_greenstein_phase(-0.7)},
          {"HG g=0.999", henyey_greenstein_phase(0.999)},
          {"HG g=-0.999", henyey_greenstein_phase(-0.999)},
          {"Rayleigh", rayleigh_phase()},
          {"Draine g=0.5 a=0.5", draine_phase(0.5, 0.5)},
          {"Draine g=-0.3 a=2", draine_phase(-0.3, 2.0)},
          {"Draine g=0.05 a=250", draine_phase(0.05, 250.0)},
          {"Draine g=0.005 a=0.5", draine_phase(0.005, 0.5)},
          {"Draine g=0.95 a=500", draine_phase(0.95, 500.0)},
          {"FF B=0.1 n=1.33", fournier_forand_phase(0.1, 1.33)},
          {"FF B=0.01 n=1.05", fournier_forand_phase(0.01, 1.05)},
          {"FF B=0.4 n=1.2", fournier_forand_phase(0.4, 1.2)},
          {"FF B=0.2 n=2", fournier_forand_phase(0.2, 2.0)},
          {"Mie d=0.05", mie_phase(0.05)},
          {"Mie d=0.7", mie_phase(0.7)},
          {"Mie d=3", mie_phase(3.0)},
          {"Mie d=20", mie_phase(20.0)},
          {"Mie d=50", mie_phase(50.0)}};
}

// The forward tail below x = 1e-300 of Fournier-Forand, from its leading term (x / x0)^-nu.
double ff_tail(const Phase& p) {
  const FournierForandCoefficients& c = p.first.ff;
  return p.first.kind == PhaseKind::FournierForand ? std::pow(1e-300 / (0.75 * (c.n - 1) * (c.n - 1)), -c.nu) : 0.0;
}

TEST(Phase, EachIntegratesToOne) {
  double worst = 0.0;
  for (const Named& n : phases()) {
    const double total = probability(of(n.phase), 0.0, 1.0) + ff_tail(n.phase);
    EXPECT_NEAR(total, 1.0, 2e-7) << n.name;
    worst = std::max(worst, std::fabs(total - 1.0));
  }
  std::printf("  largest |integral - 1|: %.2g\n", worst);
}

TEST(Phase, SamplesFollowEval) {
  const int n = test_samples(200000);
  uint64_t seed = 1;
  for (const Named& named : phases()) {
    const ChiSquare chi = sample_chi_square(named.phase, n, seed++);
    // Five standard deviations of a chi-square with `dof` degrees of freedom above its mean.
    EXPECT_LT(chi.value, chi.dof + 5.0 * std::sqrt(2.0 * chi.dof)) << named.name << " dof " << chi.dof;
    std::printf("  %-22s chi-square %7.1f, %d bins\n", named.name, chi.value, chi.dof + 1);
  }
}

// The sampler's inverse CDF against the quadrature of eval: u maps to the angle below which (HG,
// Rayleigh, Draine: cos below; Fournier-Forand: x below) a share u of the density lies. Cycles'
// isotropic HG maps u to cos = 1 - 2u, the other way round.
TEST(Phase, SampledAngleSplitsTheDensityAtU) {
  double worst = 0.0;
  for (const Named& n : phases()) {
    if (n.phase.second_weight > 0.0) continue;  // the mixture's u picks a lobe first
    for (const double u : {0.001, 0.1, 0.37, 0.5, 0.8, 0.999}) {
      const double mu = n.phase.first.sample_cos(u), x = 0.5 * (1.0 - mu);
      const bool ff = n.phase.first.kind == PhaseKind::FournierForand;
      const bool reversed = ff || (n.phase.first.kind == PhaseKind::HenyeyGreenstein && n.phase.first.g == 0.0);
      const double share =
          reversed ? probability(of(n.phase), 0.0, x) + ff_tail(n.phase) : probability(of(n.phase), x, 1.0);
      EXPECT_NEAR(share, u, 1e-7) << n.name << " u " << u;
      worst = std::max(worst, std::fabs(share - u));
    }
  }
  std::printf("  largest |share - u|: %.2g\n", worst);
}

TEST(Phase, EvalOfTheSampledDirectionIsThePdf) {
  Rng rng(3, 4, 5);
  for (const Named& n : phases()) {
    for (int i = 0; i < 2000; ++i) {
      const Vec3 d_in = glm::normalize(Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
      const PhaseSample s = n.phase.sample(d_in, rng.uniform(), rng.uniform());
      ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf > 0.0) << n.name;
      // Away from the forward peak, where the cosine of the direction rounds too coarsely.
      if (s.cos_theta < 1.0 - 1e-9) {
        EXPECT_NEAR(n.phase.eval(d_in, s.direction) / s.pdf, 1.0, 1e-5) << n.name;
      }
    }
  }
}

TEST(Phase, HenyeyGreensteinMeanCosineIsG) {
  const int n = test_samples(200000);
  for (const double g : {-0.9, -0.4, 0.2, 0.75, 0.999}) {
    const Phase p = henyey_greenstein_phase(g);
    const Density mu_p = [&](double x) { return (1.0 - 2.0 * x) * p.eval(1.0 - 2.0 * x); };
    EXPECT_NEAR(probability(mu_p, 0.0, 1.0), g, 1e-9) << g;
    Rng rng(7, 8, uint64_t(1000 * (g + 1)));
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
      const double mu = p.first.sample_cos(rng.uniform());
      sum += mu;
      sum2 += mu * mu;
    }
    const double mean = sum / n, sd = std::sqrt((sum2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, g, 5.0 * sd + 1e-12) << g;
  }
}

TEST(Phase, SmallGIsIsotropicAsInCycles) {
  for (const double g : {0.0, 5e-4, -9.9e-4}) {
    const Phase p = henyey_greenstein_phase(g);
    for (const double mu : {-1.0, -0.3, 0.0, 0.8, 1.0}) EXPECT_DOUBLE_EQ(p.eval(mu), 1.0 / (4.0 * kPi));
    EXPECT_DOUBLE_EQ(p.first.sample_cos(0.25), 0.5);  // uniform in cos
  }
  // Just above Cycles' threshold the function is HG again.
  EXPECT_NE(henyey_greenstein_phase(1.1e-3).eval(1.0), 1.0 / (4.0 * kPi));
}

// ---- The papers' formulas, evaluated again here in long double. ----
using LD = long double;
const LD kPiL = 3.141592653589793238462643383279502884L;

LD hg_ref(LD mu, LD g) { return (1 - g * g) / (4 * kPiL * std::pow(1 + g * g - 2 * g * mu, 1.5L)); }
LD rayleigh_ref(LD mu) { return 3 / (16 * kPiL) * (1 + mu * mu); }
// Draine 2003, eq. 4.
LD draine_ref(LD mu, LD g, LD a) { return hg_ref(mu, g) * (1 + a * mu * mu) / (1 + a * (1 + 2 * g * g) / 3); }

// Fournier & Jonasz 1999: the density, and nu found from the backscatter fraction by bisection of
// B(nu) = 1 - (1 - d90^(nu+1) - (1 - d90^nu) / 2) / ((1 - d90) d90^nu).
LD ff_delta(LD n, LD theta) { return 4 / (3 * (n - 1) * (n - 1)) * std::pow(std::sin(theta / 2), 2.0L); }
LD ff_backscatter(LD n, LD nu) {
  const LD d = ff_delta(n, kPiL / 2);
  return 1 - (1 - std::pow(d, nu + 1) - (1 - std::pow(d, nu)) / 2) / ((1 - d) * std::pow(d, nu));
}
LD ff_nu(LD n, LD b) {
  LD lo = -0.99999L, hi = -1e-9L;  // B grows as nu falls
  for (int i = 0; i < 200; ++i) {
    const LD mid = (lo + hi) / 2;
    (ff_backscatter(n, mid) > b ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}
LD ff_ref(LD theta, LD n, LD b) {
  const LD nu = ff_nu(n, b), d = ff_delta(n, theta), d180 = ff_delta(n, kPiL), s2 = std::pow(std::sin(theta / 2), 2.0L);
  const LD dn = std::pow(d, nu), d180n = std::pow(d180, nu);
  const LD first = (nu * (1 - d) - (1 - dn) + (d * (1 - dn) - nu * (1 - d)) / s2) / (4 * kPiL * (1 - d) * (1 - d) * dn);
  return first + (1 - d180n) / (16 * kPiL * (d180 - 1) * d180n) * (3 * std::pow(std::cos(theta), 2.0L) - 1);
}

TEST(Phase, ValuesMatchThePapersFormulas) {
  for (const LD mu : {-1.0L, -0.6L, 0.0L, 0.35L, 0.9L, 0.999L, 1.0L}) {
    for (const LD g : {-0.999L, -0.5L, 0.3L, 0.8L, 0.999L}) {
      EXPECT_NEAR(phase_henyey_greenstein(double(mu), double(g)) / double(hg_ref(mu, g)), 1.0, 1e-12);
      for (const LD a : {0.1L, 1.0L, 30.0L, 500.0L})
        EXPECT_NEAR(phase_draine(double(mu), double(g), double(a)) / double(draine_ref(mu, g, a)), 1.0, 1e-12);
    }
    EXPECT_NEAR(phase_rayleigh(double(mu)) / double(rayleigh_ref(mu)), 1.0, 1e-14);
  }
  double worst = 0.0;
  for (const LD n : {1.05L, 1.2L, 1.33L, 1.7L, 2.0L})
    for (const LD b : {0.01L, 0.1L, 0.3L, 0.45L})
      for (const LD theta : {1e-4L, 0.01L, 0.3L, 1.0L, 2.0L, 3.1L}) {
        const FournierForandCoefficients c = fournier_forand_phase(double(b), double(n)).first.ff;
        const double got = phase_fournier_forand(std::cos(double(theta)), c);
        const double want = double(ff_ref(theta, n, b));
        EXPECT_NEAR(got / want, 1.0, 1e-7) << "n " << double(n) << " B " << double(b) << " theta " << double(theta);
        worst = std::max(worst, std::fabs(got / want - 1.0));
      }
  std::printf("  Fournier-Forand: largest relative difference from the paper's form %.2g\n", worst);
}

// Jendersie & d'Eon 2023 (supplemental), eqs. 7-22, again; the ranges' ends are the doubles 0.1 and
// 1.5, as the diameter arrives (the fit jumps there: g_hg is 0.138 at d = 0.1 and 0.104 just above).
MieParameters mie_ref(LD d) {
  LD ghg, gd, a, w;
  if (d <= LD(0.1)) {
    ghg = 13.8L * d * d, gd = 1.1456L * d * std::sin(9.29044L * d);
    a = 250, w = 0.252977L - 312.983L * std::pow(d, 4.3L);
  } else if (d < LD(1.5)) {
    const LD l = std::log(d);
    ghg = 0.862L - 0.143L * l * l;
    gd = 0.379685L * std::cos(1.19692L * std::cos((l - 0.238604L) * (l + 1.00667L) / (0.507522L - 0.15677L * l)) +
                              1.37932L * l + 0.0625835L) + 0.344213L;
    a = 250, w = 0.146209L * std::cos(3.38707L * l + 2.11193L) + 0.316072L + 0.0778917L * l;
  } else if (d < 5) {
    const LD l = std::log(d);
    ghg = 0.0604931L * std::log(l) + 0.940256L, gd = 0.500411L - 0.081287L / (-2 * l + std::tan(l) + 1.27551L);
    a = 7.30354L * l + 6.31675L, w = 0.026914L * (l - std::cos(5.68947L * (std::log(l) - 0.0292149L))) + 0.3764L;
  } else {
    ghg = std::exp(-0.0990567L / (d - 1.67154L)), gd = std::exp(-2.20679L / (d + 3.91029L) - 0.428934L);
    a = std::exp(3.62489L - 8.29288L / (d + 5.52825L)), w = std::exp(-0.599085L / (d - 0.641583L) - 0.665888L);
  }
  return {double(ghg), double(gd), double(a), double(w)};
}

TEST(Phase, MieIsCyclesMixtureOfHenyeyGreensteinAndDraine) {
  for (const double d : {0.0, 0.01, 0.1, 0.5, 1.49, 1.5, 3.0, 4.99, 5.0, 20.0, 50.0}) {
    const MieParameters want = mie_ref(d), got = mie_fitted_parameters(d);
    EXPECT_NEAR(got.g_hg, want.g_hg, 1e-12) << d;
    EXPECT_NEAR(got.g_draine, want.g_draine, 1e-12) << d;
    EXPECT_NEAR(got.alpha, want.alpha, 1e-9) << d;
    EXPECT_NEAR(got.draine_weight, want.draine_weight, 1e-12) << d;
    const Phase p = mie_phase(d);
    const LD g_hg = std::min(want.g_hg, 0.999), g_d = std::min(want.g_draine, 0.999);
    for (const double mu : {-1.0, -0.2, 0.5, 0.99, 1.0}) {
      // Cycles' Draine is Rayleigh where |g| < 1e-3 and alpha > 0.999 (tiny droplets).
      const LD draine = std::fabs(double(g_d)) < 1e-3 ? rayleigh_ref(mu) : draine_ref(mu, g_d, want.alpha);
      const LD hg = std::fabs(double(g_hg)) < 1e-3 ? 1 / (4 * kPiL) : hg_ref(mu, g_hg);
      const LD ref = (1 - want.draine_weight) * hg + want.draine_weight * draine;
      EXPECT_NEAR(p.eval(mu) / double(ref), 1.0, 1e-12) << "d " << d << " mu " << mu;
    }
  }
}

TEST(Phase, FournierForandBackscatterFractionIsB) {
  for (const double n : {1.02, 1.1, 1.33, 1.6, 1.9, 2.0})
    for (const double b : {0.005, 0.05, 0.2, 0.45}) {
      const Phase p = fournier_forand_phase(b, n);
      EXPECT_NEAR(probability(of(p), 0.5, 1.0), b, 1e-9) << n << " " << b;
      for (double x = 1e-12; x < 1.0; x *= 1.5)
        EXPECT_GE(phase_fournier_forand_at(x, p.first.ff), 0.0) << n << " " << b << " " << x;
    }
}

TEST(Phase, CyclesSpecialCasesAndClamps) {
  // Draine: alpha 0 is HG, g 0 with alpha > 0.999 is Rayleigh (Cycles' phase_draine).
  EXPECT_DOUBLE_EQ(phase_draine(0.3, 0.6, 0.0), phase_henyey_greenstein(0.3, 0.6));
  EXPECT_DOUBLE_EQ(phase_draine(0.3, 0.0, 250.0), phase_rayleigh(0.3));
  EXPECT_DOUBLE_EQ(draine_phase(0.0, 250.0).first.sample_cos(0.3), sample_rayleigh_cos(0.3));
  // g to +-0.999, NaN to 0; alpha to >= 0.
  EXPECT_DOUBLE_EQ(henyey_greenstein_phase(1.0).first.g, 0.999);
  EXPECT_DOUBLE_EQ(henyey_greenstein_phase(-kInf).first.g, -0.999);
  EXPECT_DOUBLE_EQ(henyey_greenstein_phase(std::nan("")).first.g, 0.0);
  EXPECT_DOUBLE_EQ(draine_phase(0.2, -5.0).first.alpha, 0.0);
  // Fournier-Forand: B from |B| up to 0.499, IOR from 1.001.
  EXPECT_DOUBLE_EQ(fournier_forand_phase(-0.2, 1.33).first.ff.nu, fournier_forand_phase(0.2, 1.33).first.ff.nu);
  EXPECT_DOUBLE_EQ(fournier_forand_phase(0.9, 1.33).first.ff.nu, fournier_forand_phase(0.499, 1.33).first.ff.nu);
  EXPECT_DOUBLE_EQ(fournier_forand_phase(0.1, 0.5).first.ff.n, 1.001);
  // B = 0 is a forward delta that Cycles evaluates as 0 everywhere (the scattered light is lost).
  const Phase none = fournier_forand_phase(0.0, 1.33);
  EXPECT_EQ(none.eval(0.3), 0.0);
  EXPECT_EQ(none.sample(Vec3(0, 0, 1), 0.4, 0.6).pdf, 0.0);
  // Cycles' FF is 0 at exactly forward and backward.
  EXPECT_EQ(fournier_forand_phase(0.1, 1.33).eval(1.0), 0.0);
}

TEST(Phase, ExtremeParametersAndGrazingDirectionsStayFinite) {
  const std::vector<Phase> extreme = {henyey_greenstein_phase(0.999), henyey_greenstein_phase(-0.999),
                                      henyey_greenstein_phase(kInf), draine_phase(0.999, 500.0),
                                      draine_phase(-0.999, 1e300), draine_phase(1e-4, 0.5),
                                      fournier_forand_phase(0.499, 1.001), fournier_forand_phase(1e-6, 1.33),
                                      fournier_forand_phase(0.3, 1e9), fournier_forand_phase(0.25, 1.8165),
                                      mie_phase(-1.0), mie_phase(kInf), mie_phase(std::nan("")), mie_phase(1e-30)};
  const std::vector<Vec3> axes = {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 0, 0), glm::normalize(Vec3(1e-12, 0, -1)),
                                  glm::normalize(Vec3(0, 1e-300, 1))};
  Rng rng(9, 9, 9);
  for (size_t k = 0; k < extreme.size(); ++k) {
    const Phase& p = extreme[k];
    for (const double mu : {-1.0, -1.0 + 1e-16, 0.0, 1.0 - 1e-16, 1.0}) {
      EXPECT_TRUE(std::isfinite(p.eval(mu))) << k << " " << mu;
      EXPECT_GE(p.eval(mu), 0.0) << k;
    }
    for (const Vec3& axis : axes)
      for (const double u : {0.0, 1e-300, 0.5, 1.0 - 0x1p-53, rng.uniform()}) {
        const PhaseSample s = p.sample(axis, u, u);
        EXPECT_TRUE(is_finite(s.direction) && std::isfinite(s.pdf)) << k;
        EXPECT_NEAR(glm::length(s.direction), 1.0, 1e-12) << k;
      }
  }
}

}  // namespace
}  // namespace ppm
