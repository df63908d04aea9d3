// Cycles' light passes (Diffuse, Glossy and Transmission; Direct, Indirect and Color), and the
// caustic part, as a photon mapper splits its light (Settings::component_passes).
//
// Cycles files a path's light by the first surface the camera ray scatters at: by the kind of
// the lobe it scatters by there, and as Direct when the light arrives after that one scattering
// (emission it sees next, a light sampled there), Indirect otherwise. Here:
//  - an eye chain that bounced at a mirror or through glass before its hit point files all it
//    finds by that first bounce's kind (its `route`): emission seen after one bounce as Direct,
//    everything else (later emission, the hit point's direct light and photons) as Indirect;
//  - a hit point the camera sees directly splits its direct light and its photons by the class
//    of the lobes that scatter them (bsdf_eval_classes): direct light as Direct, photons as
//    Indirect;
//  - the Color passes are each class's albedo at the first surface the camera sees.
// The caustic part is the light of photons whose every scattering before the hit point was at a
// mirror or through glass (L S+ D): part of the Indirect passes, kept apart as well.
//
// Media, as Cycles' Volume Direct and Indirect: a path whose first scattering is in a volume files
// its light there, light sampled at that scattering as Direct, the rest as Indirect; emission seen
// at no bounce is Emit, a volume's too. An eye path here ends at its first scattering in a medium,
// at a hit point in the medium (hit_point.h's VolumeHitPoint), so:
//  - one the camera sees directly (no bounce on its route) files its sampled direct light as
//    Volume Direct and its volume photons as Volume Indirect;
//  - one past a mirror or glass files both as its route's Indirect, as Cycles does after a surface
//    bounce;
//  - the medium's emission along eye paths is emission as any other: Emit at no bounce, else its
//    route's Direct or Indirect (emission_component).
// Where Cycles follows a path on past its volume scattering and files the emission it meets there
// as Volume Direct (the next segment) or Indirect, no eye path here goes on: photons carry that
// light, all of it Volume Indirect. Volume photons have no caustic part (the Caustic pass is
// surface photons' L S+ D only).
#pragma once

#include "math/types.h"
#include "shading/light_class.h"

#include <cstdint>

namespace ppm {

constexpr uint8_t kNoBounce = kLightClasses;  // a route: the camera sees the hit point directly

enum LightComponent : uint8_t {
  kDiffuseDirect,
  kDiffuseIndirect,
  kGlossyDirect,
  kGlossyIndirect,
  kTransmissionDirect,
  kTransmissionIndirect,
  kVolumeDirect,
  kVolumeIndirect,
  kCaustic,  // part of the Indirect ones
  kLightComponents
};

// Where a hit point on eye-chain route `route` files the light it samples through lobes of class
// `c`: that class's Direct when the camera sees it, else its route's Indirect.
inline LightComponent direct_component(uint8_t route, int c) {
  return static_cast<LightComponent>(route == kNoBounce ? 2 * c : 2 * route + 1);
}
// Photon flux kept by Indirect component: slot k < kLightClasses is that class's Indirect, the
// last slot the caustic part.
inline LightComponent photon_slot_component(int k) {
  return k < kLightClasses ? static_cast<LightComponent>(2 * k + 1) : kCaustic;
}
// The slot of the photons a hit point on `route` gathers through lobes of class `c`: their Indirect.
inline int photon_slot(uint8_t route, int c) { return route == kNoBounce ? c : route; }
// Where emission an eye chain on `route` (a bounce's class) sees after `depth` >= 1 bounces goes.
inline LightComponent emission_component(uint8_t route, int depth) {
  return static_cast<LightComponent>(2 * route + (depth == 1 ? 0 : 1));
}

// A hit point in a medium files its light by slot: slot k < kLightClasses is route k's Indirect (it
// was reached past a mirror or glass), the last slot the Volume passes (the camera sees it).
constexpr int kVolumeSlots = kLightClasses + 1;
inline int volume_slot(uint8_t route) { return route == kNoBounce ? kLightClasses : route; }
// Where a slot's direct light and its photons go.
inline LightComponent volume_direct_component(int slot) {
  return slot == kLightClasses ? kVolumeDirect : static_cast<LightComponent>(2 * slot + 1);
}
inline LightComponent volume_photon_component(int slot) {
  return slot == kLightClasses ? kVolumeIndirect : static_cast<LightComponent>(2 * slot + 1);
}

// Flux kept at a radius over passes, by slot: the pending flux `found` joins tau_m, and once the
// progressive update folds the pixel's pending photons (`ratio` > 0, progressive_update's result)
// tau_m joins tau times that ratio, as the pixel's own tau does.
inline void fold_slots(Vec3f tau[], Vec3f tau_m[], const Vec3f found[], int slots, double ratio) {
  for (int k = 0; k < slots; ++k) {
    tau_m[k] += found[k];
    if (ratio > 0.0) {
      tau[k] = (tau[k] + tau_m[k]) * static_cast<float>(ratio);
      tau_m[k] = Vec3f(0.0f);
    }
  }
}

// A pixel's light by component, and its Color passes.
struct ComponentLight {
  Vec3f light[kLightComponents];
  Vec3f color[kLightClasses];
};

// A hit point's share of the components, beside its HitPointStats (FillVector: create as {}, all
// zero): its direct-light sums by class, and its photon flux by class (the caustic part last) at the
// current radius and pending, folded by the same progressive update as the totals.
constexpr int kPhotonParts = kLightClasses + 1;
struct HitPointComponents {
  Vec3f direct[kLightClasses];
  Vec3f tau[kPhotonParts];
  Vec3f tau_m[kPhotonParts];

  // The progressive update folded the pending photons in with `ratio` (progressive_update's result).
  void fold(double ratio) {
    if (ratio <= 0.0) return;
    for (int k = 0; k < kPhotonParts; ++k) {
      tau[k] = (tau[k] + tau_m[k]) * static_cast<float>(ratio);
      tau_m[k] = Vec3f(0.0f);
    }
  }
  // Adds to `out` the light this hit point holds: direct sums times `direct_scale`, photon flux
  // times `photon_scale` (flux to radiance at its radius).
  void add_to(ComponentLight& out, uint8_t route, double direct_scale, double photon_scale) const {
    for (int c = 0; c < kLightClasses; ++c) {
      out.light[direct_component(route, c)] += direct[c] * static_cast<float>(direct_scale);
      out.light[photon_slot_component(photon_slot(route, c))] += (tau[c] + tau_m[c]) * static_cast<float>(photon_scale);
    }
    out.light[kCaustic] += (tau[kLightClasses] + tau_m[kLightClasses]) * static_cast<float>(photon_scale);
  }
};
static_assert(sizeof(HitPointComponents) == 132, "HitPointComponents grew");

// A pixel's light components across passes (stochastic hit points): the running means of the light
// that needs no photons and of the Color passes, and its photon flux by slot, folded as the pixel's
// own flux is.
struct PixelComponents {
  ComponentLight mean;
  Vec3f tau[kPhotonParts];
  Vec3f tau_m[kPhotonParts];

  // Folds pass number `pass` (1 for the first): its light and its photons' flux by slot, with the
  // ratio progressive_update folded the pixel's pending photons in with (0: they stay pending).
  void fold(const ComponentLight& light, const Vec3f found[kPhotonParts], uint64_t pass, double ratio) {
    const float w = 1.0f / static_cast<float>(pass);
    for (int k = 0; k < kLightComponents; ++k) mean.light[k] += (light.light[k] - mean.light[k]) * w;
    for (int c = 0; c < kLightClasses; ++c) mean.color[c] += (light.color[c] - mean.color[c]) * w;
    fold_slots(tau, tau_m, found, kPhotonParts, ratio);
  }
  // The pixel's light components, its flux taken to radiance by `photon_scale`.
  ComponentLight value(double photon_scale) const {
    ComponentLight out = mean;
    for (int k = 0; k < kPhotonParts; ++k)
      out.light[photon_slot_component(k)] += (tau[k] + tau_m[k]) * static_cast<float>(photon_scale);
    return out;
  }
};
static_assert(sizeof(PixelComponents) == 240, "PixelComponents grew");

// A pixel's volume photon flux by slot across passes (stochastic hit points, progressive radii, in
// scenes with media), folded with the ratio of the pixel's volume statistics (the 3-D rule).
struct PixelVolumeComponents {
  Vec3f tau[kVolumeSlots];
  Vec3f tau_m[kVolumeSlots];

  void fold(const Vec3f found[kVolumeSlots], double ratio) { fold_slots(tau, tau_m, found, kVolumeSlots, ratio); }
  // Adds its light to `out`, the flux taken to radiance by `photon_scale` (the volume estimate's).
  void add_to(ComponentLight& out, double photon_scale) const {
    for (int k = 0; k < kVolumeSlots; ++k)
      out.light[volume_photon_component(k)] += (tau[k] + tau_m[k]) * static_cast<float>(photon_scale);
  }
};
static_assert(sizeof(PixelVolumeComponents) == 96, "PixelVolumeComponents grew");

}  // namespace ppm
