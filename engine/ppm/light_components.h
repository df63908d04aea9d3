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
    for (int k = 0; k < kPhotonParts; ++k) {
      tau_m[k] += found[k];
      if (ratio > 0.0) {
        tau[k] = (tau[k] + tau_m[k]) * static_cast<float>(ratio);
        tau_m[k] = Vec3f(0.0f);
      }
    }
  }
  // The pixel's light components, its flux taken to radiance by `photon_scale`.
  ComponentLight value(double photon_scale) const {
    ComponentLight out = mean;
    for (int k = 0; k < kPhotonParts; ++k)
      out.light[photon_slot_component(k)] += (tau[k] + tau_m[k]) * static_cast<float>(photon_scale);
    return out;
  }
};
static_assert(sizeof(PixelComponents) == 216, "PixelComponents grew");

}  // namespace ppm
