// Materials: one kind each, chosen by the exporter; a mixture holds weighted lobes (Blender's
// Mix and Add shaders, the Principled BSDF's layers). Parameters follow Blender's meaning (base
// colour, roughness, IOR). Any kind may also emit: `emission` is radiance in W/(m^2 sr) per colour
// channel (Blender's colour * strength), leaving both sides of the surface as in Cycles.
#pragma once

#include "math/types.h"
#include "shading/texture.h"
#include "shading/closure.h"
#include "shading/node_program.h"

#include <algorithm>
#include <string>
#include <vector>

namespace ppm {

enum class MaterialKind : uint8_t {
  Diffuse,  // Lambertian, base_color or texture
  Mirror,   // ideal mirror reflecting base_color
  Metal,    // conductor: Schlick Fresnel with F0 = base_color and F82 tint (Hoffman 2023); GGX if rough
  Glass,    // dielectric Fresnel with `ior`; transmission tinted by base_color; GGX if rough
  Emission, // black surface that only emits
  Holdout,  // black surface that cuts a hole in the image: alpha 0 where camera rays reach it (Cycles' Holdout)
  Mixture,  // weighted lobes (shading/closure.h); base_color is their summed colour (an albedo bound)
};

// The normal a mixture's shaders see (Blender's Normal Map node on the shaders' Normal, or a node
// program's normal): from a mixture input. Tangent and World read the input's colour c as the
// normal 2c - 1 in the tangent space of the mesh's UV map (tangent, bitangent = sign * N x T, the
// interpolated normal N) or in world space, then N + (that - N) * strength, normalised, as Cycles
// (which blends a tangent-space normal before normalising it);
// Direct takes the input as the world-space normal itself (a Bump or Normal Map node evaluated by
// the program). Light at the terminator is softened as the Blender version's Cycles does
// (shading/scatter.h).
struct NormalMap {
  enum Space : uint8_t { Tangent, World, Direct };
  int8_t input = -1;  // none
  Space space = Tangent;
  BumpSoftening softening = BumpSoftening::ContyEstevez;
  double strength = 1.0;
  // Blender 3.x's Cycles: the normal is turned, towards the geometric one, until the viewer's mirror
  // direction lies at least a little above the surface (shading/valid_reflection.h).
  bool valid_reflection = false;
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
  std::vector<Lobe> lobes;     // Mixture only
  // Mixture and emission only: computes the material's inputs (at most kMaxInputs outputs).
  NodeProgram program;
  int8_t emission_input = -1;         // `emission` times this input (a textured emission colour)
  NormalMap normal_map;               // Mixture only
  double holdout = 0.0;        // Mixture only: the weight of its Holdout closures (alpha it cuts for camera rays)
  // The medium inside the closed mesh the material is on (Scene::add_medium's index; -1: none), and
  // whether it has a surface: false makes it a boundary only (scene/medium.h), crossed unchanged.
  int32_t medium = -1;
  bool surface = true;

  bool emits() const { return max_component(emission) > 0.0; }
};

// Adds a mixture's lobes. Those `textured` take the material's texture as their colour: they share
// one input, the texture's RGB, added to the program for the first of them (none without a texture).
inline void add_lobes(Material& m, const std::vector<Lobe>& lobes, const std::vector<bool>& textured) {
  int textured_input = -1;
  for (size_t i = 0; i < lobes.size(); ++i) {
    Lobe lobe = lobes[i];
    if (textured[i] && m.texture >= 0) {
      if (textured_input < 0) {
        textured_input = static_cast<int>(m.program.outputs.size());
        m.program.add_image_output(m.texture, TextureChannel::Rgb);
      }
      lobe.color_input.input = static_cast<int8_t>(std::min(textured_input, kMaxInputs));
    }
    m.lobes.push_back(lobe);
  }
}

inline bool is_specular(const Material& m) {
  if (m.kind == MaterialKind::Mixture) return closure_is_followed(m.lobes);
  return m.kind == MaterialKind::Mirror ||
         ((m.kind == MaterialKind::Metal || m.kind == MaterialKind::Glass) && m.roughness < kSmoothRoughness);
}
// Whether the eye pass follows some of the surface (all of it, or lobes of a mixture).
inline bool has_followed(const Material& m) {
  return is_specular(m) || (m.kind == MaterialKind::Mixture && closure_has_followed(m.lobes));
}
inline bool is_black(const Material& m) { return m.kind == MaterialKind::Emission || m.kind == MaterialKind::Holdout; }
// Whether light scatters through the surface at a lobe hit points store (photons on its far side count).
inline bool transmits(const Material& m) {
  return m.kind == MaterialKind::Glass || (m.kind == MaterialKind::Mixture && closure_transmits(m.lobes));
}

}  // namespace ppm
