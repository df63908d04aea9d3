// Cycles' light-path limits (Render > Light Paths > Max Bounces: total,
// diffuse, glossy, transmission; and each light's and the world's own Max
// Bounces) as a photon mapper can honour them.
//
// A full path from the camera to a light scatters at the eye chain's mirrors
// and glass, at the hit point, then at the photon's surfaces from its last back
// to its first, where the light arrives. Cycles counts every scattering a path
// continues from, by kind, and compares a light's own limit with the total.
// Here the eye chain keeps its counts per hit point, and a photon its own: its
// scatterings after the first, plus the hit point's (classified where the
// photon lands: diffuse on a diffuse surface, otherwise glossy; a rough glass
// hit point turns that into transmission for photons from its other side).
// A photon counts for a hit point when the two counts together stay within
// every limit. A light's own limit L enters as a head start of (total - L) on
// the photon's total: chain + photon <= L then reads as chain + photon + total
// - L <= total.
#pragma once

#include "geometry/ray.h"
#include "ppm/settings.h"
#include "scene/scene.h"

#include <algorithm>
#include <cstdint>

namespace ppm {

// Counts of scatterings, saturating at 255 (limits above that count as 255, so
// only paths longer than 255 bounces could pass a limit they should not).
// Create as Bounces{} (all zero); a plain record, for FillVector.
struct Bounces {
  uint8_t total, diffuse, glossy, transmission;
};

constexpr int kBounceCap = 255;

inline uint8_t capped(int n) { return static_cast<uint8_t>(std::clamp(n, 0, kBounceCap)); }

// `b` plus one scattering that sent a ray of `kind` (kDiffuseRay, kGlossyRay or kTransmissionRay).
inline Bounces plus(Bounces b, uint8_t kind) {
  b.total = capped(b.total + 1);
  if (kind == kDiffuseRay) b.diffuse = capped(b.diffuse + 1);
  if (kind == kGlossyRay) b.glossy = capped(b.glossy + 1);
  if (kind == kTransmissionRay) b.transmission = capped(b.transmission + 1);
  return b;
}

inline bool within(const Bounces& b, const Bounces& limit) {
  return b.total <= limit.total && b.diffuse <= limit.diffuse && b.glossy <= limit.glossy &&
         b.transmission <= limit.transmission;
}

struct BounceLimits {
  bool active = false;  // false: nothing to count (no setting and no light asks for a limit)
  bool by_kind = false; // the scene's Cycles limits are honoured (Settings::light_path_limits)
  Bounces max{};        // per kind; all kBounceCap unless by_kind

  static BounceLimits of(const Settings& settings, const Scene& scene) {
    BounceLimits l;
    l.by_kind = settings.light_path_limits;
    l.max = l.by_kind ? Bounces{capped(settings.total_bounces), capped(settings.diffuse_bounces),
                                capped(settings.glossy_bounces), capped(settings.transmission_bounces)}
                      : Bounces{kBounceCap, kBounceCap, kBounceCap, kBounceCap};
    l.active = l.by_kind;
    for (const Light& light : scene.lights()) l.active = l.active || light.max_bounces < l.max.total;
    return l;
  }

  // What a hit point whose eye chain scattered `chain` leaves for the photons.
  Bounces budget(const Bounces& chain) const {
    return Bounces{capped(max.total - chain.total), capped(max.diffuse - chain.diffuse),
                   capped(max.glossy - chain.glossy), capped(max.transmission - chain.transmission)};
  }

  // A photon's counts as it leaves `light`: the head start for the light's own limit.
  Bounces start(const Light& light) const { return Bounces{capped(max.total - light.max_bounces), 0, 0, 0}; }
};

// A photon that landed on the other side of a rough glass hit point scatters there by
// transmission, not by the reflection it was counted with.
inline Bounces through_glass(Bounces b) {
  if (b.glossy > 0) {
    --b.glossy;
    b.transmission = capped(b.transmission + 1);
  }
  return b;
}

}  // namespace ppm
