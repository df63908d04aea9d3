// Free paths (shading/free_path.h): homogeneous transmittance and Cycles' chromatic distance
// sampling, unbiased per channel; delta and ratio tracking through a density ramp against the
// analytic optical depth; random walks that lose nothing where nothing absorbs (furnace) and match
// closed forms where something does (albedo^k per walker, the rod model's slab); bad coefficients,
// densities and majorants give finite, non-negative answers within the step cap.
#include "math/rng.h"
#include "shading/free_path.h"
#include "shading/phase.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace ppm {
namespace {

// Mean and its standard error, per channel.
struct Tally {
  Color sum{0.0}, sum2{0.0};
  int n = 0;
  void add(const Color& v) {
    sum += v;
    sum2 += v * v;
    ++n;
  }
  Color mean() const { return sum / double(n); }
  Color error() const { return glm::sqrt(glm::max(sum2 / double(n) - mean() * mean(), Color(0.0)) / double(n)); }
};

void expect_mean(const Tally& t, const Color& want, const char* what) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(t.mean()[c], want[c], 5.0 * t.error()[c] + 1e-12) << what << " channel " << c;
  std::printf("  %-34s mean (%.6g %.6g %.6g) want (%.6g %.6g %.6g) (%.1f %.1f %.1f) sigma\n", what, t.mean().x,
              t.mean().y, t.mean().z, want.x, want.y, want.z, (t.mean().x - want.x) / (t.error().x + 1e-300),
              (t.mean().y - want.y) / (t.error().y + 1e-300), (t.mean().z - want.z) / (t.error().z + 1e-300));
}

TEST(FreePath, TransmittanceIsExpOfOpticalDepth) {
  const Color tr = transmittance(Color(0.0, 0.7, 40.0), 0.25);
  EXPECT_DOUBLE_EQ(tr.x, 1.0);
  EXPECT_DOUBLE_EQ(tr.y, std::exp(-0.175));
  EXPECT_DOUBLE_EQ(tr.z, std::exp(-10.0));
  // A clear channel over an infinite distance, and bad coefficients: NaN and negative as clear,
  // infinite as opaque.
  EXPECT_EQ(transmittance(Color(0.0), kInf), Color(1.0));
  EXPECT_EQ(transmittance(Color(std::nan(""), -3.0, kInf), 2.0), Color(1.0, 1.0, 0.0));
  EXPECT_EQ(transmittance(Color(kInf), 0.0), Color(1.0));
  EXPECT_EQ(transmittance(Color(1.0), std::nan("")), Color(1.0));
}

// Grey, non-absorbing: scatter distances follow sigma exp(-sigma t) on [0, d) and the rest passes.
TEST(FreePath, DistancesFollowTheExponential) {
  const double sigma = 2.0, d = 1.5;
  const int n = test_samples(400000), bins = 30;
  std::vector<double> counts(bins + 1, 0.0);  // the last: through to the end
  Rng rng(21, 0, 0);
  for (int i = 0; i < n; ++i) {
    const FreePathSample s = sample_free_path(Color(sigma), Color(sigma), Color(1.0), d, rng.uniform(), rng.uniform());
    ASSERT_NEAR(s.weight.x, 1.0, 1e-12);  // sigma_s T / (sigma_t T), or T / T
    counts[s.event == FreePathEvent::Exit ? bins : std::min(bins - 1, int(s.distance / d * bins))] += 1.0;
  }
  double chi = 0.0;
  for (int b = 0; b <= bins; ++b) {
    const double p = b == bins ? std::exp(-sigma * d)
                               : std::exp(-sigma * d * b / bins) - std::exp(-sigma * d * (b + 1) / bins);
    chi += (counts[b] - n * p) * (counts[b] - n * p) / (n * p);
  }
  std::printf("  distance histogram: chi-square %.1f over %d bins\n", chi, bins + 1);
  EXPECT_LT(chi, bins + 5.0 * std::sqrt(2.0 * bins));
}

// Three very different channels, uneven throughput: the mean weight of paths that pass equals each
// channel's transmittance, and the mean weight of those that scatter its albedo times (1 - T).
TEST(FreePath, ChromaticSamplingIsUnbiasedPerChannel) {
  const Color sigma_t(0.1, 2.0, 30.0), albedo(0.9, 0.5, 0.2), sigma_s = sigma_t * albedo, throughput(1.0, 0.2, 3.0);
  const double d = 0.5;
  const int n = test_samples(400000);
  Tally passed, scattered;
  Rng rng(22, 0, 0);
  for (int i = 0; i < n; ++i) {
    const FreePathSample s = sample_free_path(sigma_t, sigma_s, throughput, d, rng.uniform(), rng.uniform());
    passed.add(s.event == FreePathEvent::Exit ? s.weight : Color(0.0));
    scattered.add(s.event == FreePathEvent::Scatter ? s.weight : Color(0.0));
  }
  expect_mean(passed, transmittance(sigma_t, d), "passed weight = T");
  expect_mean(scattered, albedo * (Color(1.0) - transmittance(sigma_t, d)), "scattered weight = albedo (1 - T)");
}

TEST(FreePath, AnAbsorberIsCrossedWithItsTransmittance) {
  const FreePathSample s = sample_free_path(Color(1.0, 2.0, 3.0), Color(0.0), Color(1.0), 0.5, 0.3, 0.99);
  EXPECT_EQ(s.event, FreePathEvent::Exit);
  EXPECT_EQ(s.weight, transmittance(Color(1.0, 2.0, 3.0), 0.5));
}

// sigma(t) = 0.5 + 2.5 t / d on [0, d]: optical depth 1.75 d.
struct Ramp {
  double d;
  double operator()(double t) const { return 0.5 + 2.5 * t / d; }
};

TEST(FreePath, TrackersMatchTheRampsTransmittance) {
  const double d = 1.2, want = std::exp(-1.75 * d);
  const int n = test_samples(200000);
  for (const double majorant : {3.0, 10.0}) {
    Rng rng(23, uint64_t(majorant), 0);
    auto uniform = [&] { return rng.uniform(); };
    double ratio = 0.0, ratio2 = 0.0, passed = 0.0;
    for (int i = 0; i < n; ++i) {
      const double t = ratio_track(Ramp{d}, majorant, d, uniform).transmittance;
      ratio += t;
      ratio2 += t * t;
      passed += delta_track(Ramp{d}, majorant, d, uniform).end == TrackingEnd::Exit;
    }
    const double ratio_mean = ratio / n, ratio_error = std::sqrt((ratio2 / n - ratio_mean * ratio_mean) / n);
    const double delta_mean = passed / n, delta_error = std::sqrt(want * (1.0 - want) / n);
    std::printf("  majorant %g: ratio tracking %.5f (%.1f sigma), delta tracking %.5f (%.1f sigma), exp(-tau) %.5f\n",
                majorant, ratio_mean, (ratio_mean - want) / ratio_error, delta_mean, (delta_mean - want) / delta_error,
                want);
    EXPECT_NEAR(ratio_mean, want, 5.0 * ratio_error);
    EXPECT_NEAR(delta_mean, want, 5.0 * delta_error);
  }
}

// Delta tracking's collisions are distributed as sigma(t) exp(-integral_0^t sigma).
TEST(FreePath, DeltaTrackingCollisionsFollowTheDensity) {
  const double d = 1.2;
  const int n = test_samples(200000), bins = 24;
  std::vector<double> counts(bins + 1, 0.0);
  Rng rng(24, 0, 0);
  auto uniform = [&] { return rng.uniform(); };
  for (int i = 0; i < n; ++i) {
    const DeltaTrackingResult r = delta_track(Ramp{d}, 4.0, d, uniform);
    counts[r.end == TrackingEnd::Exit ? bins : std::min(bins - 1, int(r.distance / d * bins))] += 1.0;
  }
  const auto depth = [&](double t) { return 0.5 * t + 1.25 * t * t / d; };
  double chi = 0.0;
  for (int b = 0; b <= bins; ++b) {
    const double p = b == bins ? std::exp(-depth(d))
                               : std::exp(-depth(d * b / bins)) - std::exp(-depth(d * (b + 1) / bins));
    chi += (counts[b] - n * p) * (counts[b] - n * p) / (n * p);
  }
  std::printf("  delta tracking collisions: chi-square %.1f over %d bins\n", chi, bins + 1);
  EXPECT_LT(chi, bins + 5.0 * std::sqrt(2.0 * bins));
}

// ---- Random walks: the samplers and the phase functions together. ----

double to_sphere_exit(const Vec3& p, const Vec3& d) {  // from inside the unit sphere
  const double b = glm::dot(p, d), c = glm::dot(p, p) - 1.0;
  return -b + std::sqrt(std::max(0.0, b * b - c));
}

struct Walk {
  Color weight{1.0};
  int scatterings = 0;
  bool exited = false;
};

Walk walk_in_unit_sphere(const Color& sigma_t, const Color& sigma_s, const Phase& phase, Rng& rng) {
  Walk w;
  Vec3 p(0.0), dir(0.0, 0.0, 1.0);
  for (int bounce = 0; bounce < 100000; ++bounce) {
    const FreePathSample s =
        sample_free_path(sigma_t, sigma_s, w.weight, to_sphere_exit(p, dir), rng.uniform(), rng.uniform());
    w.weight *= s.weight;
    if (s.event == FreePathEvent::Exit) {
      w.exited = true;
      return w;
    }
    p += s.distance * dir;
    dir = glm::normalize(phase.sample(dir, rng.uniform(), rng.uniform()).direction);  // weight: eval / pdf = 1
    ++w.scatterings;
  }
  return w;
}

std::vector<Phase> walk_phases() {
  return {henyey_greenstein_phase(0.0),     henyey_greenstein_phase(0.9), henyey_greenstein_phase(-0.6),
          rayleigh_phase(),                 draine_phase(0.4, 3.0),       fournier_forand_phase(0.1, 1.33),
          mie_phase(20.0)};
}

// Nothing absorbs: every walker leaves the sphere. Grey: with weight exactly 1. Three channels of
// different extinction: weights vary, their mean is 1 in each channel.
TEST(FreePath, FurnaceSphereLosesNothing) {
  const int n = test_samples(20000);
  int phase_index = 0;
  for (const Phase& phase : walk_phases()) {
    Rng rng(25, uint64_t(phase_index++), 0);
    double mean_scatterings = 0.0;
    for (int i = 0; i < n; ++i) {
      const Walk w = walk_in_unit_sphere(Color(4.0), Color(4.0), phase, rng);
      ASSERT_TRUE(w.exited);
      ASSERT_NEAR(w.weight.x, 1.0, 1e-12);
      ASSERT_NEAR(w.weight.z, 1.0, 1e-12);
      mean_scatterings += w.scatterings;
    }
    Tally chromatic;
    for (int i = 0; i < n; ++i) {
      const Walk w = walk_in_unit_sphere(Color(1.0, 4.0, 12.0), Color(1.0, 4.0, 12.0), phase, rng);
      ASSERT_TRUE(w.exited);
      chromatic.add(w.weight);
    }
    char what[64];
    std::snprintf(what, sizeof(what), "furnace, phase %d (%.1f scatterings)", phase_index - 1, mean_scatterings / n);
    expect_mean(chromatic, Color(1.0), what);
  }
}

// Grey absorbing sphere: each walker's weight is albedo^k after k scatterings, exactly.
TEST(FreePath, AbsorbingSphereWeighsAlbedoPerScattering) {
  const double albedo = 0.7;
  Rng rng(26, 0, 0);
  for (int i = 0; i < test_samples(5000); ++i) {
    const Walk w = walk_in_unit_sphere(Color(5.0), Color(5.0 * albedo), henyey_greenstein_phase(0.3), rng);
    ASSERT_TRUE(w.exited);
    ASSERT_NEAR(w.weight.y / std::pow(albedo, w.scatterings), 1.0, 1e-12);
  }
}

// The rod model (scattering only forward or back, each with probability 1/2) in a slab of optical
// thickness tau and albedo a has closed forms: with k = sqrt(1 - a), D = (1 + k^2) sinh(k tau) +
// 2k cosh(k tau), transmission 2k / D and reflection (1 - k^2) sinh(k tau) / D. Three channels of
// different extinction and albedo share each walk (chromatic sampling, throughput-weighted).
TEST(FreePath, RodSlabMatchesClosedForm) {
  const Color sigma_t(0.5, 2.0, 6.0), albedo(0.99, 0.5, 0.8), sigma_s = sigma_t * albedo;
  const double length = 1.0;
  const int n = test_samples(200000);
  Tally transmitted, reflected;
  Rng rng(27, 0, 0);
  for (int i = 0; i < n; ++i) {
    Color weight(1.0);
    double x = 0.0, dir = 1.0;
    for (int bounce = 0; bounce < 100000; ++bounce) {
      const double segment = dir > 0.0 ? length - x : x;
      const FreePathSample s = sample_free_path(sigma_t, sigma_s, weight, segment, rng.uniform(), rng.uniform());
      weight *= s.weight;
      if (s.event == FreePathEvent::Exit) break;
      x += dir * s.distance;
      dir = rng.uniform() < 0.5 ? 1.0 : -1.0;
    }
    transmitted.add(dir > 0.0 ? weight : Color(0.0));
    reflected.add(dir > 0.0 ? Color(0.0) : weight);
  }
  Color want_t, want_r;
  for (int c = 0; c < 3; ++c) {
    const double k = std::sqrt(1.0 - albedo[c]), tau = sigma_t[c] * length;
    const double denominator = (1.0 + k * k) * std::sinh(k * tau) + 2.0 * k * std::cosh(k * tau);
    want_t[c] = 2.0 * k / denominator;
    want_r[c] = (1.0 - k * k) * std::sinh(k * tau) / denominator;
  }
  expect_mean(transmitted, want_t, "rod slab transmission");
  expect_mean(reflected, want_r, "rod slab reflection");
}

// ---- Bad input. ----

TEST(FreePath, BadCoefficientsGiveFiniteNonNegativeWeights) {
  const double nan = std::nan("");
  const std::vector<Color> bad = {Color(nan), Color(-1.0, 2.0, nan), Color(kInf, 1.0, 0.0), Color(-kInf), Color(0.0),
                                  Color(1e308, 1e-308, 3.0)};
  Rng rng(28, 0, 0);
  for (const Color& sigma_t : bad)
    for (const Color& sigma_s : bad)
      for (const Color& throughput : {Color(1.0), Color(nan, 1.0, -2.0), Color(0.0)})
        for (const double segment : {0.0, 1.0, kInf, nan, -1.0})
          for (int i = 0; i < 20; ++i) {
            const FreePathSample s =
                sample_free_path(sigma_t, sigma_s, throughput, segment, rng.uniform(), rng.uniform());
            ASSERT_TRUE(is_finite(s.weight) && s.weight.x >= 0.0 && s.weight.y >= 0.0 && s.weight.z >= 0.0)
                << sigma_t.x << " " << sigma_t.y << " " << sigma_s.y << " " << segment;
            ASSERT_TRUE(s.distance >= 0.0 && !std::isnan(s.distance));
            ASSERT_TRUE(s.event == FreePathEvent::Scatter ? std::isfinite(s.distance) : true);
          }
  // Out-of-range random numbers too.
  for (const double u : {nan, -1.0, 1.0, 2.0, kInf}) {
    const FreePathSample s = sample_free_path(Color(1.0, 2.0, 3.0), Color(0.5), Color(1.0), 1.0, u, u);
    EXPECT_TRUE(is_finite(s.weight) && std::isfinite(s.distance));
  }
}

TEST(FreePath, BadDensitiesAndMajorantsNeverHang) {
  Rng rng(29, 0, 0);
  auto uniform = [&] { return rng.uniform(); };
  const double nan = std::nan("");
  // NaN and negative densities count as 0: nothing collides.
  for (const double bad : {nan, -5.0, -kInf}) {
    const auto density = [bad](double) { return bad; };
    EXPECT_EQ(ratio_track(density, 2.0, 1.0, uniform).transmittance, 1.0);
    EXPECT_EQ(delta_track(density, 2.0, 1.0, uniform).end, TrackingEnd::Exit);
  }
  // Infinite densities (and any above the majorant) count as the majorant.
  const auto infinite = [](double) { return kInf; };
  int passed = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(ratio_track(infinite, 2.0, 1.0, uniform).transmittance >= 0.0, true);
    passed += delta_track(infinite, 2.0, 1.0, uniform).end == TrackingEnd::Exit;
  }
  EXPECT_NEAR(double(passed) / n, std::exp(-2.0), 5.0 * std::sqrt(std::exp(-2.0) / n));
  // A majorant of 0 or NaN: an empty medium; an infinite one is opaque.
  const auto ramp = Ramp{1.0};
  EXPECT_EQ(ratio_track(ramp, 0.0, 1.0, uniform).transmittance, 1.0);
  EXPECT_EQ(ratio_track(ramp, nan, 1.0, uniform).transmittance, 1.0);
  EXPECT_EQ(delta_track(ramp, -1.0, 1.0, uniform).end, TrackingEnd::Exit);
  // An empty infinite medium under a majorant, or a majorant far above a thin density: the step
  // cap ends the walk, and says so.
  const auto empty = [](double) { return 0.0; };
  const DeltaTrackingResult capped = delta_track(empty, 1.0, kInf, uniform, 1000);
  EXPECT_EQ(capped.end, TrackingEnd::StepCap);
  EXPECT_EQ(capped.steps, 1000);
  const RatioTrackingResult capped_ratio = ratio_track(empty, kInf, 1.0, uniform);
  EXPECT_TRUE(capped_ratio.capped);
  EXPECT_EQ(capped_ratio.transmittance, 0.0);
  EXPECT_EQ(capped_ratio.steps, kMaxTrackingSteps);
  // A NaN or negative segment is empty.
  EXPECT_EQ(ratio_track(ramp, 3.0, nan, uniform).transmittance, 1.0);
  EXPECT_EQ(delta_track(ramp, 3.0, -2.0, uniform).end, TrackingEnd::Exit);
}

}  // namespace
}  // namespace ppm
