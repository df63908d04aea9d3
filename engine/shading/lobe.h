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
                // `tint`, refraction by `color`
};

constexpr int kLayerAlbedoSteps = 32;  // a layer's directional albedo, tabulated by cos(theta)
constexpr int kMaxLobes = 8;

struct Lobe {
  LobeKind kind = LobeKind::Diffuse;
  uint8_t parts = kReflectionAndRefraction;  // Dielectric only
  bool layer = false;  // attenuates every lobe after it by 1 - (its directional albedo towards the viewer)
  bool textured = false;  // `color` times the material's texture (SurfacePoint::albedo)
  Color weight{1.0};
  Color color{0.8};
  Color tint{1.0};
  double roughness = 0.0;
  double ior = 1.5;
  std::array<float, kLayerAlbedoSteps> albedo{};  // filled by prepare_lobe for layers

  bool delta() const {
    return kind == LobeKind::Transparent ||
           ((kind == LobeKind::Conductor || kind == LobeKind::Glossy || kind == LobeKind::Dielectric) &&
            roughness < kSmoothRoughness);
  }
  bool diffuse() const { return kind == LobeKind::Diffuse || kind == LobeKind::Translucent; }
  Color color_at(const Color& texel) const { return textured ? color * texel : color; }
};

}  // namespace ppm
