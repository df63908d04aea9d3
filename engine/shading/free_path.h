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
// Media that vary along the segment (RGB coefficients at each point): null-collision tracking against
// a majorant (Woodcock et al. 1965; Novak et al. 2014; Kutz et al. 2017's spectral tracking), which
// samples a real scattering, or with scattering off is ratio tracking and estimates transmittance.
// The coefficients come from a template callable, so no virtual call happens per step.
//
// Bad input never hangs and never leaves finite arithmetic: a coefficient or density that is NaN or
// negative counts as 0; +inf, or anything above kMaxCoefficient, as kMaxCoefficient (opaque); in the
// tracker a density above the majorant counts as the majorant (the majorant must bound it; where
// it does not, the answer is biased, never undefined). A NaN or negative distance counts as 0; an
// infinite one is allowed. The tracker stops after max_steps and says so (TrackedSegment::capped).
#pragma once

#include "math/types.h"

#include <algorithm>
#include <utility>
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
  // The channels' probabilities: the free path reaches t with probability sum_c pdf_c T_c(t).
  Color channel_pdf{1.0 / 3.0};
};

// A point at distance `height` > 0 from the ray, its foot at `foot` along it. Equiangular sampling
// over [0, d] draws t with density height / ((theta_b - theta_a) (height^2 + (t - foot)^2)): uniform
// in the angle the point sees t under, proportional to 1 / distance^2 to it. Not usable where the
// point lies on the ray's line or sees the segment under no angle (a point mass is no density).
struct EquiangularTarget {
  double foot = 0.0, height = 0.0;
  static EquiangularTarget of(const Vec3& origin, const Vec3& direction, const Vec3& point) {
    const Vec3 to = point - origin;
    const double foot = glm::dot(to, direction);
    return {foot, glm::length(to - foot * direction)};
  }
  double span(double d) const { return std::atan2(d - foot, height) - std::atan2(-foot, height); }
  bool usable(double d) const {
    return height > 0.0 && std::isfinite(height) && std::isfinite(foot) && d > 0.0 && span(d) > 0.0;
  }
  double sample(double d, double u) const;
  double pdf(double d, double t) const;
};

// One segment of length `segment` (may be infinite) through a homogeneous medium. Scatter at t:
// weight sigma_s T(t) / sum_c pdf_c sigma_t,c T_c(t) (then the phase function is sampled, whose
// value equals its pdf); through to the end: T(d) / sum_c pdf_c T_c(d). A medium that only absorbs
// (sigma_s = 0) is not sampled: the segment is crossed with weight T(d), as Cycles does.
FreePathSample sample_free_path(const Color& sigma_t, const Color& sigma_s, const Color& throughput, double segment,
                                double u_channel, double u_distance);

// The same drawn within the segment (a collision for sure, where any channel can have one): the
// channel's exponential truncated to [0, segment), weight sigma_s T(t) / sum_c pdf_c sigma_t,c T_c(t)
// / (1 - T_c(segment)); a channel without extinction draws uniformly over a finite segment. Exit
// (weight 0) where nothing can collide.
// With `toward` (a light near the ray), half the draws are equiangular towards it instead
// (EquiangularTarget) and the density in the weight is the two's mean, so that the scatterings near
// a small light, where its light is strongest, are drawn as often as that light needs (Kulla and
// Fajardo 2012; Cycles' homogeneous volumes do the same by multiple importance).
FreePathSample sample_free_path_within(const Color& sigma_t, const Color& sigma_s, const Color& throughput,
                                       double segment, double u_channel, double u_distance,
                                       const EquiangularTarget* toward = nullptr);

// A density as the tracker counts it (see the top): within [0, majorant].
inline double tracked_density(double sigma, double majorant) { return sigma > 0.0 ? std::min(sigma, majorant) : 0.0; }

// ---- Heterogeneous RGB media: one tracker for eye paths, photons and shadow rays. ----

// A medium's extinction, scattering and emission at a point along the segment, as the tracker
// asks for them (`at(t)` returns one).
struct TrackedCoefficients {
  Color sigma_t{0.0}, sigma_s{0.0}, emission{0.0};
};

struct TrackedSegment {
  FreePathEvent event = FreePathEvent::Exit;
  double distance = 0.0;  // to the scattering, or the segment's length
  Color weight{1.0};      // what the path's throughput is multiplied by (a scattering's sigma_s included)
  Color unit{0.0};        // Scatter: `weight` without the point's sigma_s (a volume hit point's weight)
  Color emitted{0.0};     // the emission met before the event: an estimate of int_0^t T(s) e(s) ds
  int steps = 0;          // tentative collisions drawn
  bool capped = false;    // stopped at max_steps (counted as absorbed)
};

// Null-collision tracking of an RGB medium against a scalar majorant m >= every channel's sigma_t
// (Kutz et al. 2017's spectral tracking, absorption in the weight): tentative collisions at rate m;
// at each, a scattering with probability P_s = <f sigma_s> / (<f sigma_s> + <f sigma_n>), where f is
// `throughput` times the weight so far, <.> the mean over channels and sigma_n = m - sigma_t the null
// part; else a null collision. The weight takes sigma_s / (m P_s) or sigma_n / (m (1 - P_s)), so
// that per channel the expected weight carried past a point is its transmittance and a scattering
// at t has density sigma_s(t) T(t). A grey medium that does not absorb is plain delta tracking
// (weights 1). With `may_scatter` false it is ratio tracking: the weight at the end estimates T.
// Emission is summed at the tentative collisions (e / m each, times the weight there). Below a
// weight of kTrackingRoulette Russian roulette ends the walk early (unbiased; where little is left,
// so it adds little noise). The step cap counts as absorbed.
constexpr double kTrackingRoulette = 0.01;

// A majorant that varies along the segment (a majorant grid's cells, scene/majorant_grid.h): pieces
// [previous end, end) each with its majorant, from next(); the last piece's end reaches the segment's.
struct MajorantPiece {
  double end = kInf;
  double majorant = 0.0;
};
struct ConstantMajorant {  // one piece over everything
  double majorant;
  MajorantPiece next() const { return {kInf, majorant}; }
};

// The same as track_segment below, against a majorant that is constant over each of the pieces
// `majorants.next()` gives in turn: tentative collisions at each piece's rate (an optical depth
// drawn once, spent piece by piece), so that empty space (a majorant of 0) costs no collision.
template <class At, class Majorants, class Uniform>
TrackedSegment track_segment_pieces(const At& at, Majorants& majorants, double segment, const Color& throughput,
                                    bool may_scatter, Uniform&& uniform, int max_steps = kMaxTrackingSteps) {
  TrackedSegment out;
  const double d = safe_distance(segment);
  out.distance = d;
  MajorantPiece piece = majorants.next();
  double m = safe_coefficient(piece.majorant);
  double t = 0.0;
  Color w(1.0);
  const auto absorbed = [&](double at) {
    out.distance = std::min(at, d);
    out.weight = Color(0.0);
    return out;
  };
  for (int step = 1; step <= max_steps; ++step) {
    out.steps = step;
    double depth = -std::log1p(-safe_uniform(uniform()));  // optical depth to the next tentative collision
    for (;;) {  // spend it over the pieces
      const double next = m > 0.0 ? t + depth / m : kInf;
      if (next < piece.end || !(piece.end < d)) {
        t = next;
        break;
      }
      depth -= (piece.end - t) * m;
      t = piece.end;
      piece = majorants.next();
      m = safe_coefficient(piece.majorant);
    }
    if (!(t < d)) {
      out.weight = w;
      return out;
    }
    const TrackedCoefficients c = at(t);
    Color sigma_s(0.0), sigma_n(0.0);
    for (int k = 0; k < 3; ++k) {
      const double st = tracked_density(c.sigma_t[k], m);
      sigma_s[k] = may_scatter ? std::min(safe_coefficient(c.sigma_s[k]), st) : 0.0;
      sigma_n[k] = m - st;
      const double e = c.emission[k];
      if (e > 0.0 && e < kInf) out.emitted[k] += w[k] * e / m;
    }
    const Color f = throughput * w;
    const double a_s = (f.x * sigma_s.x + f.y * sigma_s.y + f.z * sigma_s.z) / 3.0;
    const double a_n = (f.x * sigma_n.x + f.y * sigma_n.y + f.z * sigma_n.z) / 3.0;
    if (!(a_s + a_n > 0.0)) return absorbed(t);  // nothing goes on from here
    const double p_s = a_s / (a_s + a_n);
    if (safe_uniform(uniform()) < p_s) {
      out.event = FreePathEvent::Scatter;
      out.distance = t;
      out.unit = w / (m * p_s);
      out.weight = out.unit * sigma_s;
      return out;
    }
    w *= sigma_n / (m * (1.0 - p_s));
    const double peak = max_component(w);
    if (peak < kTrackingRoulette) {
      if (!(peak > 0.0) || safe_uniform(uniform()) * kTrackingRoulette >= peak) return absorbed(t);
      w *= kTrackingRoulette / peak;
    }
  }
  out.capped = true;
  return absorbed(t);
}

template <class At, class Uniform>
TrackedSegment track_segment(const At& at, double majorant, double segment, const Color& throughput,
                             bool may_scatter, Uniform&& uniform, int max_steps = kMaxTrackingSteps) {
  if (!(safe_coefficient(majorant) > 0.0)) {
    TrackedSegment out;
    out.distance = safe_distance(segment);
    return out;
  }
  ConstantMajorant constant{majorant};
  return track_segment_pieces(at, constant, segment, throughput, may_scatter, std::forward<Uniform>(uniform),
                              max_steps);
}

}  // namespace ppm
