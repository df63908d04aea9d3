// Materials: one kind each, chosen by the exporter. Parameters follow Blender's
// meaning (base colour, roughness, IOR). Any kind may also emit: `emission` is
// radiance in W/(m^2 sr) per colour channel (Blender's colour * strength),
// leaving both sides of the surface as in Cycles.
#pragma once

#include "math/types.h"

#include <string>

namespace ppm {

enum class MaterialKind : uint8_t {
  Diffuse,  // Lambertian, base_color or texture
  Mirror,   // ideal mirror reflecting base_color
  Metal,    // conductor: Schlick Fresnel with F0 = base_color and F82 tint (Hoffman 2023); GGX if rough
  Glass,    // dielectric Fresnel with `ior`; transmission tinted by base_color; GGX if rough
  Emission, // black surface that only emits
  Holdout,  // black surface that cuts a hole in the image: alpha 0 where camera rays reach it (Cycles' Holdout)
};

struct Material {
  std::string name;
  MaterialKind kind = MaterialKind::Diffuse;
  Color base_color{0.8};
  int texture = -1;            // index into Scene textures, -1 = none
  double roughness = 0.0;      // GGX alpha = roughness^2 (Blender's mapping)
  double ior = 1.45;
  Color specular_tint{1.0};    // metal: F82 tint
  Color emission{0.0};

  bool emits() const { return max_component(emission) > 0.0; }
};

// Below this roughness a surface is treated as perfectly smooth: the eye pass
// follows it and photons pass it without depositing.
constexpr double kSmoothRoughness = 1e-3;

inline bool is_specular(const Material& m) {
  return m.kind == MaterialKind::Mirror ||
         ((m.kind == MaterialKind::Metal || m.kind == MaterialKind::Glass) && m.roughness < kSmoothRoughness);
}
inline bool is_black(const Material& m) { return m.kind == MaterialKind::Emission || m.kind == MaterialKind::Holdout; }

}  // namespace ppm
