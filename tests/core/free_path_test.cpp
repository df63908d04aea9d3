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

// The split camera path's sampler (volume beams): a collision for sure, inside the segment, whose
// weight still averages to albedo (1 - T) per channel; a clear channel draws uniformly, and a
// segment where nothing can collide gives Exit.
TEST(FreePath, SamplingWithinTheSegmentIsUnbiasedPerChannel) {
  const Color sigma_t(0.1, 2.0, 0.0), sigma_s(0.09, 1.0, 0.0), throughput(1.0, 0.2, 3.0);
  const Color albedo(0.9, 0.5, 0.0);
  const double d = 0.5;
  const int n = test_samples(400000);
  Tally scattered;
  Rng rng(23, 0, 0);
  for (int i = 0; i < n; ++i) {
    const FreePathSample s = sample_free_path_within(sigma_t, sigma_s, throughput, d, rng.uniform(), rng.uniform());
    ASSERT_EQ(s.event, FreePathEvent::Scatter);
    ASSERT_GE(s.distance, 0.0);
    ASSERT_LE(s.distance, d);
    scattered.add(s.weight);
  }
  expect_mean(scattered, albedo * (Color(1.0) - transmittance(sigma_t, d)), "scattered weight = albedo (1 - T)");
  const FreePathSample none = sample_free_path_within(Color(0.0), Color(0.0), throughput, d, 0.5, 0.5);
  EXPECT_EQ(none.event, FreePathEvent::Exit);
  const FreePathSample endless = sample_free_path_within(Color(0.0, 1.0, 0.0), Color(0.0, 1.0, 0.0), Color(1.0, 0.0, 0.0),
                                                         kInf, 0.5, 0.5);
  EXPECT_TRUE(endless.event == FreePathEvent::Exit || std::isfinite(endless.distance));
}

// A small light 5 cm beside the segment: the in-scattered light is sigma_s T(t) / distance^2. Drawn
// half equiangular towards it, the estimate stays unbiased and its noise drops, as it is for.
TEST(FreePath, DrawingTowardsALightKeepsTheMeanAndLowersTheNoise) {
  const Color sigma_t(0.1, 2.0, 0.5), sigma_s(0.09, 1.0, 0.5), throughput(1.0, 0.2, 3.0);
  const double d = 3.0;
  const EquiangularTarget light{1.2, 0.05};
  const auto falloff = [&](double t) { return 1.0 / (light.height * light.height + (t - light.foot) * (t - light.foot)); };
  Color want(0.0);  // the midpoint rule, fine enough at the light's 5 cm
  const int steps = 200000;
  for (int i = 0; i < steps; ++i) {
    const double t = (i + 0.5) * d / steps;
    want += sigma_s * transmittance(sigma_t, t) * falloff(t) * (d / steps);
  }
  double pdf_sum = 0.0;
  for (int i = 0; i < steps; ++i) pdf_sum += light.pdf(d, (i + 0.5) * d / steps) * (d / steps);
  EXPECT_NEAR(pdf_sum, 1.0, 1e-4);
  const int n = test_samples(400000);
  Tally mixed, plain;
  Rng rng(29, 0, 0);
  for (int i = 0; i < n; ++i) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const FreePathSample a = sample_free_path_within(sigma_t, sigma_s, throughput, d, u1, u2, &light);
    const FreePathSample b = sample_free_path_within(sigma_t, sigma_s, throughput, d, u1, u2);
    ASSERT_EQ(a.event, FreePathEvent::Scatter);
    ASSERT_GE(a.distance, 0.0);
    ASSERT_LE(a.distance, d);
    mixed.add(a.weight * falloff(a.distance));
    plain.add(b.weight * falloff(b.distance));
  }
  expect_mean(mixed, want, "towards the light");
  expect_mean(plain, want, "by transmittance alone");
  // Measured 0.25-0.26 of the noise in each channel (400,000 draws); a heavy tail makes the plain
  // estimate's own error uncertain, hence the margin.
  for (int c = 0; c < 3; ++c) EXPECT_LT(mixed.error()[c], 0.4 * plain.error()[c]) << c;
  // On the light's line there is nothing to aim at: transmittance alone.
  EXPECT_FALSE((EquiangularTarget{1.0, 0.0}).usable(d));
  const EquiangularTarget behind = EquiangularTarget::of(Vec3(0.0), Vec3(1.0, 0.0, 0.0), Vec3(-2.0, 1.0, 0.0));
  EXPECT_DOUBLE_EQ(behind.foot, -2.0);
  EXPECT_DOUBLE_EQ(behind.height, 1.0);
  const double t = behind.sample(d, 0.999);
  EXPECT_TRUE(t >= 0.0 && t <= d);
}

TEST(FreePath, AnAbsorberIsCrossedWithItsTransmittance) {
  const FreePathSample s = sample_free_path(Color(1.0, 2.0, 3.0), Color(0.0), Color(1.0), 0.5, 0.3, 0.99);
  EXPECT_EQ(s.event, FreePathEvent::Exit);
  EXPECT_EQ(s.weight, transmittance(Color(1.0, 2.0, 3.0), 0.5));
}

// sigma(t) = 0.5 + 2.5 t / d on [0, d]: optical depth 1.75 d. Grey; `albedo` of it scatters, and
// `emission` (per channel, times 1 + t) is emitted.
struct Ramp {
  double d;
  Color albedo{1.0};
  Color scale{1.0};  // per channel, times the grey ramp
  Color emission{0.0};
  double sigma(double t) const { return 0.5 + 2.5 * t / d; }
  TrackedCoefficients operator()(double t) const {
    return {scale * sigma(t), scale * sigma(t) * albedo, emission * (1.0 + t)};
  }
  // Optical depth from 0 to t of channel scale 1.
  double depth(double t) const { return 0.5 * t + 1.25 * t * t / d; }
};

TrackedSegment track(const Ramp& ramp, double majorant, double segment, bool may_scatter, Rng& rng,
                     const Color& throughput = Color(1.0), int max_steps = kMaxTrackingSteps) {
  return track_segment(ramp, majorant, segment, throughput, may_scatter, [&] { return rng.uniform(); }, max_steps);
}

// Without scattering the tracker is ratio tracking: its weight's mean is exp(-tau). Scattering
// allowed in a grey medium that does not absorb, it is delta tracking: weights 1, and the share that
// passes is exp(-tau). Both for a tight majorant and a loose one.
TEST(FreePath, TrackersMatchTheRampsTransmittance) {
  const Ramp ramp{1.2};
  const double want = std::exp(-ramp.depth(ramp.d));
  const int n = test_samples(200000);
  for (const double majorant : {3.0, 10.0}) {
    Rng rng(23, uint64_t(majorant), 0);
    Tally ratio, passed;
    for (int i = 0; i < n; ++i) {
      ratio.add(track(ramp, majorant, ramp.d, false, rng).weight);
      const TrackedSegment delta = track(ramp, majorant, ramp.d, true, rng);
      ASSERT_NEAR(delta.weight.x, 1.0, 1e-12);
      passed.add(Color(delta.event == FreePathEvent::Exit ? 1.0 : 0.0));
    }
    expect_mean(ratio, Color(want), majorant < 5.0 ? "ratio tracking, majorant 3" : "ratio tracking, majorant 10");
    expect_mean(passed, Color(want), majorant < 5.0 ? "delta tracking, majorant 3" : "delta tracking, majorant 10");
  }
}

// Delta tracking's collisions are distributed as sigma(t) exp(-integral_0^t sigma).
TEST(FreePath, DeltaTrackingCollisionsFollowTheDensity) {
  const Ramp ramp{1.2};
  const int n = test_samples(200000), bins = 24;
  std::vector<double> counts(bins + 1, 0.0);
  Rng rng(24, 0, 0);
  for (int i = 0; i < n; ++i) {
    const TrackedSegment r = track(ramp, 4.0, ramp.d, true, rng);
    counts[r.event == FreePathEvent::Exit ? bins : std::min(bins - 1, int(r.distance / ramp.d * bins))] += 1.0;
  }
  double chi = 0.0;
  for (int b = 0; b <= bins; ++b) {
    const double p = b == bins ? std::exp(-ramp.depth(ramp.d))
                               : std::exp(-ramp.depth(ramp.d * b / bins)) - std::exp(-ramp.depth(ramp.d * (b + 1) / bins));
    chi += (counts[b] - n * p) * (counts[b] - n * p) / (n * p);
  }
  std::printf("  delta tracking collisions: chi-square %.1f over %d bins\n", chi, bins + 1);
  EXPECT_LT(chi, bins + 5.0 * std::sqrt(2.0 * bins));
}

// A majorant in pieces (a majorant grid's cells along the path): a medium empty over [0, 0.4) and
// the ramp beyond, against pieces of 0 there and the ramp's bound beyond (split once more at 0.7):
// ratio tracking's mean is the transmittance, delta tracking's collisions follow the density, and
// no tentative collision falls where the majorant is 0.
struct SteppedRamp {
  Ramp ramp;
  double gap;
  TrackedCoefficients operator()(double t) const {
    EXPECT_GE(t, gap) << "a tentative collision where the majorant is 0";
    return t < gap ? TrackedCoefficients{} : ramp(t);
  }
  double depth(double t) const { return t < gap ? 0.0 : ramp.depth(t) - ramp.depth(gap); }
};
struct Pieces {
  std::vector<MajorantPiece> pieces;
  size_t next_piece = 0;
  MajorantPiece next() { return pieces[std::min(next_piece++, pieces.size() - 1)]; }
};

TEST(FreePath, TrackersAgainstMajorantsInPiecesMatchTheTransmittance) {
  const SteppedRamp medium{Ramp{1.2}, 0.4};
  const double want = std::exp(-medium.depth(medium.ramp.d));
  const int n = test_samples(200000), bins = 16;
  Rng rng(25, 0, 0);
  Tally ratio, passed;
  std::vector<double> counts(bins + 1, 0.0);
  for (int i = 0; i < n; ++i) {
    Pieces a{{{0.4, 0.0}, {0.7, 2.0}, {kInf, 3.1}}}, b = a;
    ratio.add(track_segment_pieces(medium, a, medium.ramp.d, Color(1.0), false, [&] { return rng.uniform(); }).weight);
    const TrackedSegment delta = track_segment_pieces(medium, b, medium.ramp.d, Color(1.0), true,
                                                      [&] { return rng.uniform(); });
    passed.add(Color(delta.event == FreePathEvent::Exit ? 1.0 : 0.0));
    counts[delta.event == FreePathEvent::Exit ? bins : std::min(bins - 1, int(delta.distance / medium.ramp.d * bins))] += 1;
  }
  expect_mean(ratio, Color(want), "ratio tracking, majorant in pieces");
  expect_mean(passed, Color(want), "delta tracking, majorant in pieces");
  double chi = 0.0;
  int dof = 0;
  for (int b = 0; b <= bins; ++b) {
    const double d = medium.ramp.d;
    const double p = b == bins ? want : std::exp(-medium.depth(d * b / bins)) - std::exp(-medium.depth(d * (b + 1) / bins));
    if (p == 0.0) {
      EXPECT_EQ(counts[b], 0.0) << "a collision in the empty part, bin " << b;
      continue;
    }
    chi += (counts[b] - n * p) * (counts[b] - n * p) / (n * p), ++dof;
  }
  std::printf("  delta tracking in pieces: chi-square %.1f over %d bins\n", chi, dof);
  EXPECT_LT(chi, dof + 5.0 * std::sqrt(2.0 * dof));
}

// An RGB medium whose channels differ tenfold, absorbing, under an uneven throughput: per channel the
// mean weight of paths that pass is T, the mean weight of those that scatter is
// int_0^d sigma_s(t) T(t) dt, and a scattering's weight is its unit weight times sigma_s there. The
// emission met, scattering or not, averages int_0^d T(t) e(t) dt (the midpoint rule, 4000 steps).
TEST(FreePath, ChromaticTrackingIsUnbiasedPerChannel) {
  Ramp ramp{0.8};
  ramp.scale = Color(0.2, 1.0, 2.0);
  ramp.albedo = Color(0.9, 0.5, 0.3);
  ramp.emission = Color(0.3, 1.0, 2.0);
  const Color throughput(1.0, 0.2, 3.0);
  Color want_t(0.0), want_s(0.0), want_e(0.0);
  const int steps = 4000;
  for (int c = 0; c < 3; ++c) {
    want_t[c] = std::exp(-ramp.scale[c] * ramp.depth(ramp.d));
    for (int k = 0; k < steps; ++k) {
      const double t = (k + 0.5) * ramp.d / steps, tr = std::exp(-ramp.scale[c] * ramp.depth(t));
      want_s[c] += ramp(t).sigma_s[c] * tr * ramp.d / steps;
      want_e[c] += ramp(t).emission[c] * tr * ramp.d / steps;
    }
  }
  const double majorant = 2.0 * (0.5 + 2.5);
  for (const bool may_scatter : {true, false}) {
    const int n = test_samples(300000);
    Rng rng(25, may_scatter, 0);
    Tally passed, scattered, emitted;
    for (int i = 0; i < n; ++i) {
      const TrackedSegment r = track(ramp, majorant, ramp.d, may_scatter, rng, throughput);
      passed.add(r.event == FreePathEvent::Exit ? r.weight : Color(0.0));
      scattered.add(r.event == FreePathEvent::Scatter ? r.weight : Color(0.0));
      emitted.add(r.emitted);
      if (r.event == FreePathEvent::Scatter) {
        const Color expected = r.unit * ramp(r.distance).sigma_s;
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(r.weight[c], expected[c], 1e-12 * (1.0 + expected[c]));
      }
    }
    if (may_scatter) {
      expect_mean(passed, want_t, "tracked: passed weight = T");
      expect_mean(scattered, want_s, "tracked: scattered = int sigma_s T");
      expect_mean(emitted, want_e, "tracked: emission = int T e");
    } else {
      expect_mean(passed, want_t, "ratio: passed weight = T");
      expect_mean(emitted, want_e, "ratio: emission = int T e");
    }
  }
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
  auto grey = [](double sigma) { return [sigma](double) { return TrackedCoefficients{Color(sigma), Color(sigma)}; }; };
  // NaN and negative densities count as 0: nothing collides.
  for (const double bad : {nan, -5.0, -kInf}) {
    for (const bool may_scatter : {false, true}) {
      const TrackedSegment r = track_segment(grey(bad), 2.0, 1.0, Color(1.0), may_scatter, uniform);
      EXPECT_EQ(r.event, FreePathEvent::Exit);
      EXPECT_EQ(r.weight, Color(1.0));
    }
  }
  // Infinite densities (and any above the majorant) count as the majorant.
  int passed = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const TrackedSegment ratio = track_segment(grey(kInf), 2.0, 1.0, Color(1.0), false, uniform);
    EXPECT_TRUE(is_finite(ratio.weight) && ratio.weight.x >= 0.0);
    passed += track_segment(grey(kInf), 2.0, 1.0, Color(1.0), true, uniform).event == FreePathEvent::Exit;
  }
  EXPECT_NEAR(double(passed) / n, std::exp(-2.0), 5.0 * std::sqrt(std::exp(-2.0) / n));
  // A majorant of 0, NaN or below 0: an empty medium.
  const Ramp ramp{1.0};
  for (const double majorant : {0.0, nan, -1.0})
    EXPECT_EQ(track_segment(ramp, majorant, 1.0, Color(1.0), true, uniform).weight, Color(1.0));
  // An empty infinite medium under a majorant, or an infinite majorant: the step cap ends the walk as
  // absorbed, and says so.
  const TrackedSegment capped = track_segment(grey(0.0), 1.0, kInf, Color(1.0), true, uniform, 1000);
  EXPECT_TRUE(capped.capped);
  EXPECT_EQ(capped.steps, 1000);
  EXPECT_EQ(capped.weight, Color(0.0));
  const TrackedSegment opaque = track_segment(ramp, kInf, 1.0, Color(1.0), false, uniform);
  EXPECT_TRUE(opaque.capped);
  EXPECT_EQ(opaque.weight, Color(0.0));
  // A NaN or negative segment is empty; NaN emission and coefficients add nothing and stay finite.
  EXPECT_EQ(track_segment(ramp, 3.0, nan, Color(1.0), true, uniform).weight, Color(1.0));
  EXPECT_EQ(track_segment(ramp, 3.0, -2.0, Color(1.0), true, uniform).weight, Color(1.0));
  const auto broken = [nan](double) { return TrackedCoefficients{Color(nan, 1.0, kInf), Color(nan, -1.0, 1.0), Color(nan, kInf, -1.0)}; };
  for (int i = 0; i < 100; ++i) {
    const TrackedSegment r = track_segment(broken, 2.0, 1.0, Color(1.0), true, uniform);
    EXPECT_TRUE(is_finite(r.weight) && is_finite(r.emitted) && is_finite(r.unit));
  }
}

}  // namespace
}  // namespace ppm
