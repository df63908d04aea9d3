// Cycles' light-path limits (Render > Light Paths > Max Bounces: total,
// diffuse, glossy, transmission, volume; and each light's and the world's own
// Max Bounces) as a photon mapper can honour them.
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
//
// Scatterings in media count as volume (and total), as Cycles counts them: Volume
// bounces N lets a path continue from N of them, so N + 1 see direct light (0,
// Blender's default: single scattering). A hit point in a medium is a volume
// scattering of its own, counted when the photon it gathers scattered before.
#pragma once

#include "geometry/ray.h"
#include "ppm/settings.h"
#include "scene/scene.h"

#include <algorithm>
#include <cstdint>

namespace ppm {

// Counts of scatterings, saturating: the total at 255, each kind at 63 (limits above that count as
// the cap, so only paths longer than the cap could pass a limit they should not). A volume
// scattering counts as volume and total, as Cycles counts it. Four bytes, so that a photon's counts
// stay in what would be its record's padding. Create as Bounces{} (all zero); a plain record, for
// FillVector.
struct Bounces {
  uint32_t total : 8, diffuse : 6, glossy : 6, transmission : 6, volume : 6;
};
static_assert(sizeof(Bounces) == 4, "Bounces grew");

constexpr int kBounceCap = 255;
constexpr int kKindBounceCap = 63;

inline uint8_t capped(int n) { return static_cast<uint8_t>(std::clamp(n, 0, kBounceCap)); }
inline uint8_t capped_kind(int n) { return static_cast<uint8_t>(std::clamp(n, 0, kKindBounceCap)); }

// Counts from whole numbers, each saturated at its cap.
inline Bounces bounces(int total, int diffuse, int glossy, int transmission, int volume) {
  Bounces b{};
  b.total = capped(total);
  b.diffuse = capped_kind(diffuse);
  b.glossy = capped_kind(glossy);
  b.transmission = capped_kind(transmission);
  b.volume = capped_kind(volume);
  return b;
}

// `b` plus one scattering that sent a ray of `kind` (kDiffuseRay, kGlossyRay or kTransmissionRay).
inline Bounces plus(Bounces b, uint8_t kind) {
  return bounces(b.total + 1, b.diffuse + (kind == kDiffuseRay), b.glossy + (kind == kGlossyRay),
                 b.transmission + (kind == kTransmissionRay), b.volume);
}
// `b` plus one scattering in a medium.
inline Bounces plus_volume(Bounces b) {
  return bounces(b.total + 1, b.diffuse, b.glossy, b.transmission, b.volume + 1);
}

inline bool within(const Bounces& b, const Bounces& limit) {
  return b.total <= limit.total && b.diffuse <= limit.diffuse && b.glossy <= limit.glossy &&
         b.transmission <= limit.transmission && b.volume <= limit.volume;
}

struct BounceLimits {
  bool active = false;  // false: nothing to count (no setting and no light asks for a limit)
  bool by_kind = false; // the scene's Cycles limits are honoured (Settings::light_path_limits)
  Bounces max{};        // per kind; each at its cap unless by_kind

  static BounceLimits of(const Settings& settings, const Scene& scene) {
    BounceLimits l;
    l.by_kind = settings.light_path_limits;
    l.max = l.by_kind ? bounces(settings.total_bounces, settings.diffuse_bounces, settings.glossy_bounces,
                                settings.transmission_bounces, settings.volume_bounces)
                      : bounces(kBounceCap, kBounceCap, kBounceCap, kBounceCap, kBounceCap);
    l.active = l.by_kind;
    for (const Light& light : scene.lights()) l.active = l.active || light.max_bounces < l.max.total;
    return l;
  }

  // What a hit point whose eye chain scattered `chain` leaves for the photons.
  Bounces budget(const Bounces& chain) const {
    return bounces(max.total - chain.total, max.diffuse - chain.diffuse, max.glossy - chain.glossy,
                   max.transmission - chain.transmission, max.volume - chain.volume);
  }

  // A photon's counts as it leaves `light`: the head start for the light's own limit.
  Bounces start(const Light& light) const { return bounces(max.total - light.max_bounces, 0, 0, 0, 0); }
};

// A photon that landed on the other side of a rough glass hit point scatters there by
// transmission, not by the reflection it was counted with.
inline Bounces through_glass(Bounces b) {
  if (b.glossy > 0) return bounces(b.total, b.diffuse, b.glossy - 1, b.transmission + 1, b.volume);
  return b;
}

}  // namespace ppm
