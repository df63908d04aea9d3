// Per-pixel statistics of stochastic progressive photon mapping (Hachisuka &
// Jensen 2009): the eye samples change every pass, so radius, photon count and
// flux live with the pixel instead of with a hit point. They are the whole of a
// render's memory that grows with the image (the hit points are made and
// dropped band by band), so they are floats: 52 bytes a pixel instead of 128 in
// doubles. Streamed fixed hit points keep the same float photon statistics per
// hit point (streamed_hit_points.h). The progressive update itself runs in
// double.
#pragma once

#include "ppm/hit_point.h"
#include "ppm/progressive.h"

namespace ppm {

// Photon statistics in float, kept across passes per pixel (stochastic hit points) or per
// streamed fixed hit point (streamed_hit_points.h).
struct FloatPhotonStats {
  float r2;          // 0 until the first hit point sets the initial radius
  float n;           // photons accumulated so far (alpha-weighted)
  uint32_t m;        // photons gathered at the current radius, not yet applied
  Vec3f tau, tau_m;  // flux at the current radius; flux of the m pending photons

  HitPointStats in_double() const { return HitPointStats{n, m, 0.0f, Color(tau), Color(tau_m), Color(0.0), 0.0f, 0}; }
  // Adds a pass's photons (`found_m`, `found_tau`), then the progressive update with the
  // cross-generation threshold, in double.
  // Returns progressive_update's ratio (0: the photons stay pending).
  double fold(uint32_t found_m, const Vec3f& found_tau, double alpha, uint32_t threshold);
  // The same with the 3-D rule, for a pixel's hit points in media (progressive_update_volume).
  double fold_volume(uint32_t found_m, const Vec3f& found_tau, double alpha, uint32_t threshold) {
    return fold_in(3, found_m, found_tau, alpha, threshold);
  }
  // fold() in a gather region of `dimensions` (progressive_update_in).
  double fold_in(int dimensions, uint32_t found_m, const Vec3f& found_tau, double alpha, uint32_t threshold);
};
static_assert(sizeof(FloatPhotonStats) == 36, "FloatPhotonStats grew");

// What a pixel keeps across passes.
struct PixelStats : FloatPhotonStats {
  Vec3f light;         // mean over passes of what eye paths saw directly: emission, background, direct light
  float transparency;  // mean over passes
};
static_assert(sizeof(PixelStats) == 52, "PixelStats grew");

// What one pass found for a pixel.
struct PixelPass {
  uint32_t m;
  Vec3f tau_m;
  Vec3f light;
  float transparency;
};
static_assert(sizeof(PixelPass) == 32, "PixelPass grew");

// The smallest r^2 a float radius keeps: the update stops shrinking there (see kMinRadius2).
constexpr double kMinPixelRadius2 = 1e-30;

inline double FloatPhotonStats::fold(uint32_t found_m, const Vec3f& found_tau, double alpha, uint32_t threshold) {
  return fold_in(2, found_m, found_tau, alpha, threshold);
}

inline double FloatPhotonStats::fold_in(int dimensions, uint32_t found_m, const Vec3f& found_tau, double alpha,
                                        uint32_t threshold) {
  HitPointStats s{n, m + found_m, 0.0f, Color(tau), Color(tau_m) + Color(found_tau), Color(0.0), 0.0f, 0};
  double r2_double = r2;
  const double ratio = progressive_update_in(dimensions, r2_double, s, alpha, threshold, kMinPixelRadius2);
  r2 = static_cast<float>(r2_double);
  n = static_cast<float>(s.n);
  m = s.m;
  tau = Vec3f(s.tau);
  tau_m = Vec3f(s.tau_m);
  return ratio;
}

// Folds pass number `pass` (1 for the first) into `px`: the running means, then the progressive
// update with the cross-generation threshold, in double.
// Returns progressive_update's ratio (0: the photons stay pending).
inline double fold_pass(PixelStats& px, const PixelPass& p, uint64_t pass, double alpha, uint32_t threshold) {
  const float w = 1.0f / static_cast<float>(pass);  // a running mean keeps float error at sqrt(passes) ulps
  px.light += (p.light - px.light) * w;
  px.transparency += (p.transparency - px.transparency) * w;
  return px.fold(p.m, p.tau_m, alpha, threshold);
}

}  // namespace ppm
