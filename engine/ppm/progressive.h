// The progressive radiance estimate of each hit point (Hachisuka et al. 2008)
// with the cross-generation rule: photons gathered at the current radius
// accumulate over passes in (m, tau_m) until m >= P; only then
//   r^2 *= (n + alpha m) / (n + m),  tau = (tau + tau_m) (n + alpha m) / (n + m),
//   n += alpha m,  m = tau_m = 0.                                    (eq. 7-10)
// P = 1 is classic PPM.
#pragma once

#include "ppm/hit_point.h"

#include <cmath>

namespace ppm {

// The smallest r^2 the update shrinks to (m^2). Far below any radius a scene
// in range can use (radii start at >= 4e-10 of the scene's extent and shrink
// like passes^-0.15 for alpha = 0.7), and far above the denormals, so that r^2,
// tau and pi r^2 N_emitted keep full precision: a radius that would shrink
// below it stops shrinking and its photons all count (ratio 1: n += m), which
// keeps the estimate tau / (pi r^2) consistent instead of dividing by zero.
constexpr double kMinRadius2 = 1e-200;

// The update in a gather region of `dimensions` (2: a disc on a surface; 3: a sphere in a medium).
// PPM's rule keeps the photon density over the region: N / V = (N + alpha M) / V', so the region
// shrinks by the ratio, r^d *= (n + alpha m) / (n + m), r^2 by its 2/d power, and tau by the ratio
// itself (the photons the smaller region keeps). Knaus & Zwicker (2011) reach the same from the
// variance-bias balance: in d dimensions the variance grows as r^-d and the bias as r^2, and the
// sequence r_i^d = r_1^d prod (k + alpha) / (k + 1) makes both vanish (their volumetric photon
// points: d = 3). Returns the ratio the pending photons were folded in with (tau = (tau + tau_m) *
// ratio), or 0 if they stay pending: what the light components follow (light_components.h).
inline double progressive_update_in(int dimensions, double& r2, HitPointStats& s, double alpha, uint32_t threshold,
                                    double min_r2 = kMinRadius2) {
  if (s.m < threshold || s.m == 0) return 0.0;
  const double m = static_cast<double>(s.m);
  double ratio = (s.n + alpha * m) / (s.n + m);
  const double r2_ratio = dimensions == 2 ? ratio : std::pow(ratio, 2.0 / dimensions);
  if (r2 * r2_ratio >= min_r2) {
    r2 *= r2_ratio;
    s.tau = (s.tau + s.tau_m) * ratio;
    s.n += alpha * m;
  } else {
    ratio = 1.0;
    s.tau += s.tau_m;
    s.n += m;
  }
  s.m = 0;
  s.tau_m = Color(0.0);
  return ratio;
}

// A hit point on a surface (eq. 7-10 above).
inline double progressive_update(double& r2, HitPointStats& s, double alpha, uint32_t threshold,
                                 double min_r2 = kMinRadius2) {
  return progressive_update_in(2, r2, s, alpha, threshold, min_r2);
}

// A hit point in a medium, its photons gathered in a sphere (a 3-D density estimate).
inline double progressive_update_volume(double& r2, HitPointStats& s, double alpha, uint32_t threshold,
                                        double min_r2 = kMinRadius2) {
  return progressive_update_in(3, r2, s, alpha, threshold, min_r2);
}

// The volume estimate: flux per volume of the sphere, (tau + tau_m) / (4/3 pi r^3 N_emitted). The
// photons' flux already carries sigma_s (photon_tracer_media.h), so this is sigma_s times the
// in-scattered radiance, and hit points in media weigh it by their throughput over sigma_s.
inline Color volume_photon_radiance(double r2, const HitPointStats& s, double photons_emitted, double flux_unit) {
  if (photons_emitted <= 0.0 || r2 <= 0.0) return Color(0.0);
  const double volume = 4.0 / 3.0 * kPi * r2 * std::sqrt(r2);
  return (s.tau + s.tau_m) * (flux_unit / (volume * photons_emitted));
}

// Photon part of the radiance: flux per area per emitted photon. The pending
// (tau_m, m) photons were gathered at the current radius r, exactly like
// those already in tau, so they belong in the estimate: leaving them out would
// darken every hit point that waits for P photons while N_emitted grows.
// Photons carry shares of the lights' total flux: `flux_unit` is that total.
inline Color photon_radiance(double r2, const HitPointStats& s, double photons_emitted, double flux_unit) {
  if (photons_emitted <= 0.0 || r2 <= 0.0) return Color(0.0);
  return (s.tau + s.tau_m) * (flux_unit / (kPi * r2 * photons_emitted));
}

}  // namespace ppm
