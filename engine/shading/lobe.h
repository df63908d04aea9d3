// One weighted lobe of a mixture material (Blender's shader closures after Mix and Add shaders
// are folded into weights at export). Parameters follow Blender's meaning.
#pragma once

#include "math/types.h"
#include "shading/lobes.h"

#include <array>


namespace ppm {

enum class LobeKind : uint8_t {
  Diffuse,      // Lambertian reflection of `color`
  Translucent,  // Lambertian transmission of `color` to the far side
  Transparent,  // straight through, tinted by `color` (a delta lobe; Cycles' Transparent BSDF)
  Conductor,    // GGX (a mirror when smooth): F0 = `color`, F82 tint = `tint`
  Glossy,       // GGX (a mirror when smooth) reflecting `color` at every angle (Cycles' Glossy BSDF)
  Dielectric,   // GGX (smooth: delta) with the Fresnel of `ior`: `parts` of it, reflection tinted by
                // `tint`, refraction by `color`; refraction alone has no Fresnel (Cycles' Refraction BSDF)
};

constexpr int kMaxLobes = 8;
// Below this roughness a mixture's glossy lobe is sampled by eye paths, as a mirror is followed:
// photons gathered in a radius resolve it poorly (against Cycles 5.0, tests/blenders/
// materials_compare.py: a Principled coat of roughness 0.03 was 16% dark and rough glass of 0.2 3%
// bright when gathered; 2.2% and 1.0% when followed; glass of roughness 0.3 is within 0.6% gathered).
constexpr double kFollowedRoughness = 0.25;
constexpr int kLayerAlbedoSteps = 32;  // a layer's directional albedo, tabulated by cos(theta)

struct Lobe {
  LobeKind kind = LobeKind::Diffuse;
  uint8_t parts = kReflectionAndRefraction;  // Dielectric only
  bool layer = false;  // attenuates every lobe after it by 1 - (its directional albedo towards the viewer)
  bool textured = false;  // `color` times the material's texture (SurfacePoint::albedo)
  bool multiscatter = false;  // GGX energy lost to single scattering restored, as Cycles' Multiscatter GGX
  bool tint_f0 = false;       // Dielectric: `tint` scales F0 only (see DielectricParams)
  Color weight{1.0};
  Color color{0.8};
  Color tint{1.0};
  double roughness = 0.0;
  double ior = 1.5;
  std::array<float, kLayerAlbedoSteps> albedo{};  // a layer's, multiple scattering included (prepare_lobe)

  bool delta() const {
    return kind == LobeKind::Transparent ||
           ((kind == LobeKind::Conductor || kind == LobeKind::Glossy || kind == LobeKind::Dielectric) &&
            roughness < kSmoothRoughness);
  }
  // Followed by eye paths rather than stored in a hit point: delta lobes, and glossy ones too narrow
  // for a photon density estimate to resolve (see kFollowedRoughness).
  bool followed() const { return delta() || (!diffuse() && kind != LobeKind::Transparent && roughness < kFollowedRoughness); }
  bool diffuse() const { return kind == LobeKind::Diffuse || kind == LobeKind::Translucent; }
  Color color_at(const Color& texel) const { return textured ? color * texel : color; }
  DielectricParams dielectric(const Color& texel) const {
    return {ior, roughness, tint, color_at(texel), parts, tint_f0};
  }
};

}  // namespace ppm
