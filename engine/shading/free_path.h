// Free paths through participating media: how far a path goes before it collides, and what it
// carries across a stretch it does not collide in. One set of samplers for volumes and random-walk
// subsurface, eye paths and photon paths alike (docs: "Media").
//
// Homogeneous media (per-channel RGB coefficients): transmittance exp(-sigma_t d), and Cycles'
// chromatic distance sampling (volume_integrate_step_scattering of Cycles 3.x-4.x): a channel is
// picked with probability proportional to |throughput * albedo| (volume_sample_channel, after
// Chiang et al. 2016), the distance is drawn from that channel's exponential, and the weight divides
// by the density averaged over the channels with those probabilities (the one-sample model with the
// balance heuristic, "spectral MIS"), so each channel's estimate stays unbiased.
//
// Heterogeneous media (a scalar extinction along the segment, e.g. density times a grey sigma_t):
// delta tracking samples a real collision, ratio tracking estimates transmittance, both against a
// majorant (Woodcock et al. 1965; Novak et al. 2014). The density is a template callable, so no
// virtual call happens per step.
//
// Bad input never hangs and never leaves finite arithmetic: a coefficient or density that is NaN or
// negative counts as 0; +inf, or anything above kMaxCoefficient, as kMaxCoefficient (opaque); in the
// trackers a density above the majorant counts as the majorant (the majorant must bound it; where
// it does not, the answer is biased, never undefined). A NaN or negative distance counts as 0; an
// infinite one is allowed. The trackers stop after max_steps and say so (TrackingEnd::StepCap).
#pragma once

#include "math/types.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ppm {

constexpr double kMaxCoefficient = 1e30;
constexpr int kMaxTrackingSteps = 1 << 16;

inline double safe_coefficient(double s) { return s > 0.0 ? std::min(s, kMaxCoefficient) : 0.0; }
inline Color safe_coefficients(const Color& c) {
  return Color(safe_coefficient(c.x), safe_coefficient(c.y), safe_coefficient(c.z));
}
inline double safe_distance(double d) { return d > 0.0 ? d : 0.0; }
// A uniform in [0, 1): NaN and out-of-range values clamped, so that -log(1 - u) stays finite.
inline double safe_uniform(double u) { return u > 0.0 ? std::min(u, 1.0 - 0x1p-53) : 0.0; }

// exp(-sigma d) of one channel; a channel without extinction transmits everything, even over an
// infinite distance (0 * inf would be NaN).
inline double channel_transmittance(double sigma, double d) {
  const double s = safe_coefficient(sigma), t = safe_distance(d);
  return s > 0.0 ? std::exp(-s * t) : 1.0;
}
inline Color transmittance(const Color& sigma_t, double d) {
  return Color(channel_transmittance(sigma_t.x, d), channel_transmittance(sigma_t.y, d),
               channel_transmittance(sigma_t.z, d));
}

struct ChannelPick {
  int channel = 0;
  Color pdf{1.0 / 3.0};  // each channel's probability
};
// Cycles' volume_sample_channel: probabilities |throughput * albedo| / sum, uniform where they are
// all 0 (or not finite). `u` is rescaled to [0, 1) within the picked channel, for reuse.
ChannelPick pick_channel(const Color& albedo, const Color& throughput, double& u);

enum class FreePathEvent : uint8_t { Scatter, Exit };

struct FreePathSample {
  FreePathEvent event = FreePathEvent::Exit;
  double distance = 0.0;  // to the scattering point, or the segment's length
  Color weight{0.0};      // what the path's throughput is multiplied by
};

// One segment of length `segment` (may be infinite) through a homogeneous medium. Scatter at t:
// weight sigma_s T(t) / sum_c pdf_c sigma_t,c T_c(t) (then the phase function is sampled, whose
// value equals its pdf); through to the end: T(d) / sum_c pdf_c T_c(d). A medium that only absorbs
// (sigma_s = 0) is not sampled: the segment is crossed with weight T(d), as Cycles does.
FreePathSample sample_free_path(const Color& sigma_t, const Color& sigma_s, const Color& throughput, double segment,
                                double u_channel, double u_distance);

// ---- Heterogeneous media: the trackers. ----

// A density as the trackers count it (see the top): within [0, majorant].
inline double tracked_density(double sigma, double majorant) { return sigma > 0.0 ? std::min(sigma, majorant) : 0.0; }

enum class TrackingEnd : uint8_t { Collision, Exit, StepCap };

struct DeltaTrackingResult {
  TrackingEnd end = TrackingEnd::Exit;
  double distance = 0.0;  // the collision's, or the segment's length
  int steps = 0;          // tentative collisions drawn
};

// Delta tracking: tentative collisions at majorant rate, each real with probability
// sigma(t) / majorant, so the first real one is distributed as sigma(t) exp(-integral_0^t sigma).
// `sigma_t_at(t)` returns the extinction at distance t; `uniform()` returns a uniform in [0, 1).
// StepCap: no answer within max_steps (a caller counts the path as absorbed).
template <class Density, class Uniform>
DeltaTrackingResult delta_track(const Density& sigma_t_at, double majorant, double segment, Uniform&& uniform,
                                int max_steps = kMaxTrackingSteps) {
  const double m = safe_coefficient(majorant), d = safe_distance(segment);
  if (m == 0.0) return {TrackingEnd::Exit, d, 0};
  double t = 0.0;
  for (int step = 1; step <= max_steps; ++step) {
    t -= std::log1p(-safe_uniform(uniform())) / m;
    if (!(t < d)) return {TrackingEnd::Exit, d, step};
    if (safe_uniform(uniform()) * m < tracked_density(sigma_t_at(t), m)) return {TrackingEnd::Collision, t, step};
  }
  return {TrackingEnd::StepCap, t, max_steps};
}

struct RatioTrackingResult {
  double transmittance = 0.0;
  int steps = 0;
  bool capped = false;  // stopped at max_steps: transmittance 0 reported
};

// Ratio tracking: the product of (1 - sigma(t_i) / majorant) over tentative collisions t_i drawn
// at majorant rate; its mean is exp(-integral_0^d sigma). Stops early once the product is 0.
template <class Density, class Uniform>
RatioTrackingResult ratio_track(const Density& sigma_t_at, double majorant, double segment, Uniform&& uniform,
                                int max_steps = kMaxTrackingSteps) {
  const double m = safe_coefficient(majorant), d = safe_distance(segment);
  if (m == 0.0) return {1.0, 0, false};
  double t = 0.0, tr = 1.0;
  for (int step = 1; step <= max_steps; ++step) {
    t -= std::log1p(-safe_uniform(uniform())) / m;
    if (!(t < d)) return {tr, step, false};
    tr *= 1.0 - tracked_density(sigma_t_at(t), m) / m;
    if (tr == 0.0) return {0.0, step, false};
  }
  return {0.0, max_steps, true};
}

}  // namespace ppm
