// The progressive radiance estimate of each hit point (Hachisuka et al. 2008)
// with the cross-generation rule: photons gathered at the current radius
// accumulate over passes in (m, tau_m) until m >= P; only then
//   r^2 *= (n + alpha m) / (n + m),  tau = (tau + tau_m) (n + alpha m) / (n + m),
//   n += alpha m,  m = tau_m = 0.                                    (eq. 7-10)
// P = 1 is classic PPM.
#pragma once

#include "ppm/hit_point.h"

namespace ppm {

// The smallest r^2 the update shrinks to (m^2). Far below any radius a scene
// in range can use (radii start at >= 4e-10 of the scene's extent and shrink
// like passes^-0.15 for alpha = 0.7), and far above the denormals, so that r^2,
// tau and pi r^2 N_emitted keep full precision: a radius that would shrink
// below it stops shrinking and its photons all count (ratio 1: n += m), which
// keeps the estimate tau / (pi r^2) consistent instead of dividing by zero.
constexpr double kMinRadius2 = 1e-200;

// Returns the ratio the pending photons were folded in with (tau = (tau + tau_m) * ratio), or 0
// if they stay pending: what the light components follow (light_components.h).
inline double progressive_update(double& r2, HitPointStats& s, double alpha, uint32_t threshold,
                                 double min_r2 = kMinRadius2) {
  if (s.m < threshold || s.m == 0) return 0.0;
  const double m = static_cast<double>(s.m);
  double ratio = (s.n + alpha * m) / (s.n + m);
  if (r2 * ratio >= min_r2) {
    r2 *= ratio;
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
