// One weighted lobe of a mixture material (Blender's shader closures after Mix and Add shaders
// are folded into weights at export). Parameters follow Blender's meaning.
#pragma once

#include "math/types.h"
#include "shading/lobes.h"

#include <array>
#include <vector>


namespace ppm {

enum class LobeKind : uint8_t {
  Diffuse,      // Lambertian reflection of `color`; Oren-Nayar when rough (multiscatter: Blender 4.3+'s)
  Translucent,  // Lambertian transmission of `color` to the far side
  Transparent,  // straight through, tinted by `color` (a delta lobe; Cycles' Transparent BSDF)
  Conductor,    // GGX (a mirror when smooth): F0 = `color`, F82 tint = `tint`
  Glossy,       // GGX (a mirror when smooth) reflecting `color` at every angle (Cycles' Glossy BSDF)
  Dielectric,   // GGX (smooth: delta) with the Fresnel of `ior`: `parts` of it, reflection tinted by
                // `tint`, refraction by `color`; refraction alone has no Fresnel (Cycles' Refraction BSDF)
  Velvet,       // Ashikhmin's velvet sheen of `color`, sigma = `roughness` (lobes.h)
  SchlickSheen, // the 3.x Principled BSDF's sheen, `color` (1 - l.h)^5
  MicrofiberSheen,  // 4.0 and later's sheen of `color`, `roughness` (microfiber_sheen.h)
};

constexpr int kMaxLobes = 8;
constexpr double kFollowedLayerRoughness = 0.25;  // see Lobe::followed_at
constexpr int kLayerAlbedoSteps = 32;      // a layer's directional albedo, tabulated by cos(theta)
constexpr int kLayerRoughnessSteps = 17;   // ... and by roughness, when a texture drives it
constexpr int kGlassEnergySteps = 32;      // a multiscatter glass's albedo, by cos(theta)

// A lobe parameter driven by one of its material's inputs (an image texture's value at the shading
// point, SurfacePoint::inputs). A colour or roughness is the parameter's constant times the input
// (Value) or its square root (Sqrt: the Principled BSDF's transmission tints each crossing by
// sqrt(base colour)); a weight's factor is the input clamped to [0, 1] (Fraction, as Cycles clamps a
// Mix Shader's factor and the Principled BSDF's weights) or 1 minus that (Complement: the Mix
// Shader's other input). No input: the constant alone.
struct InputRef {
  enum Transform : uint8_t { Value, Sqrt, Fraction, Complement };
  int8_t input = -1;
  Transform transform = Value;

  bool used() const { return input >= 0; }
  Color apply(const SurfacePoint& sp) const {
    if (input < 0) return Color(1.0);
    const Color v(sp.inputs[input]);
    switch (transform) {
      case Sqrt: return glm::sqrt(glm::max(v, Color(0.0)));
      case Fraction: return glm::clamp(v, 0.0, 1.0);
      case Complement: return Color(1.0) - glm::clamp(v, 0.0, 1.0);
      case Value: break;
    }
    return v;
  }
};

struct Lobe {
  LobeKind kind = LobeKind::Diffuse;
  uint8_t parts = kReflectionAndRefraction;  // Dielectric only
  bool layer = false;  // attenuates every lobe after it by 1 - (its directional albedo towards the viewer)
  bool multiscatter = false;  // GGX energy lost to single scattering restored, as Cycles' Multiscatter GGX
                              // (for glass, reflection and refraction together: glass_energy)
  bool tint_f0 = false;       // Dielectric: `tint` scales F0 only (see DielectricParams)
  bool beckmann = false;      // microfacet lobes: Beckmann's distribution rather than GGX
  Color weight{1.0};
  Color color{0.8};
  Color tint{1.0};
  double roughness = 0.0;
  double ior = 1.5;
  // Anisotropy (conductor and glossy lobes): alpha times stretch_x along the surface's tangent
  // (SurfacePoint::tangent) turned by `rotation` (a fraction of a turn about the normal), and
  // stretch_y across it, as the exporter maps Blender's Anisotropy for each node.
  double stretch_x = 1.0, stretch_y = 1.0, rotation = 0.0;
  InputRef color_input, roughness_input;   // roughness: the input's first channel
  std::array<InputRef, 2> weight_inputs;   // the weight's factors from inputs (textured Mix factors)
  // A layer's directional albedo, multiple scattering included (prepare_lobe): by cos(theta), and
  // with a textured roughness by roughness too (kLayerRoughnessSteps rows).
  std::vector<float> albedo;
  // Multiscatter glass: its single-scattering albedo E (reflection plus refraction, white), by side
  // (outside, inside), roughness row as `albedo`, then cos(theta) in kGlassEnergySteps entries
  // followed by their cosine-weighted average E_avg (prepare_lobe).
  std::vector<float> glass_energy;

  double roughness_at(const SurfacePoint& sp) const {
    return roughness_input.used() ? glm::clamp(roughness * roughness_input.apply(sp).x, 0.0, 1.0) : roughness;
  }
  Color color_at(const SurfacePoint& sp) const { return color * color_input.apply(sp); }
  bool anisotropic() const { return stretch_x != 1.0 || stretch_y != 1.0; }
  Color weight_at(const SurfacePoint& sp) const {
    return weight * weight_inputs[0].apply(sp) * weight_inputs[1].apply(sp);
  }
  DielectricParams dielectric(const SurfacePoint& sp) const {
    return {ior, roughness_at(sp), tint, color_at(sp), parts, tint_f0, beckmann};
  }

  bool diffuse() const { return kind == LobeKind::Diffuse || kind == LobeKind::Translucent; }
  bool sheen() const {
    return kind == LobeKind::Velvet || kind == LobeKind::SchlickSheen || kind == LobeKind::MicrofiberSheen;
  }
  bool glass() const { return kind == LobeKind::Dielectric && parts == kReflectionAndRefraction; }
  bool microfacet() const {
    return kind == LobeKind::Conductor || kind == LobeKind::Glossy || kind == LobeKind::Dielectric;
  }
  bool delta_at(double r) const { return kind == LobeKind::Transparent || (microfacet() && r < kSmoothRoughness); }
  bool refracts() const { return kind == LobeKind::Dielectric && (parts & kRefraction); }
  // Followed by eye paths rather than stored in a hit point: delta lobes, glass, metal and glossy
  // lobes at any roughness, and layers (coats, the Principled BSDF's dielectric specular) narrower
  // than kFollowedLayerRoughness; hit points store diffuse, translucent and sheen lobes and the
  // wider layers. Eye paths sample a rough lobe and the lights it reflects (EyeTracer::
  // sample_lights). Gathered in a radius, narrow lobes were biased (against Cycles 5.0,
  // tests/blenders/materials_compare.py: a coat of roughness 0.03 16% dark, rough glass of 0.2 3%
  // bright; refraction gathered 5-9% off in a white furnace) and wide ones noisy: the rough gold
  // ball (0.25) of bench/equal_time_studio had 26 times the relative MSE at 30 s (0.106 gathered,
  // 0.0040 followed: issue 50). The Principled BSDF's wide specular layer under a coat, followed,
  // read 2.6-4% dark against Cycles at 32-64 passes (principled_coat), gathered 0.3%: layers stay
  // gathered. With a textured roughness that is decided per shading point.
  bool followed_at(double r) const {
    return delta_at(r) || refracts() || (microfacet() && (!layer || r < kFollowedLayerRoughness));
  }
  bool followed(const SurfacePoint& sp) const { return followed_at(roughness_at(sp)); }
  bool may_be_followed() const { return followed_at(roughness) || (microfacet() && roughness_input.used()); }
  bool always_followed() const { return followed_at(roughness) && !roughness_input.used(); }
  // Cycles writes its denoising features at the first lobe rougher than this (a smoother one it
  // looks through, as through a mirror).
  bool rough_for_denoising(const SurfacePoint& sp) const { return microfacet() && roughness_at(sp) > 0.075; }
};

}  // namespace ppm
