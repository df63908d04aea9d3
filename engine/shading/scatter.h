// What every scattering function shares: the surface point it scatters at and a sampled direction.
// Directions point away from the surface: `wo` towards the viewer or the previous path vertex,
// `wi` towards the light or the next vertex.
#pragma once

#include "geometry/ray.h"
#include "math/types.h"

#include <array>

namespace ppm {

constexpr int kMaxInputs = 8;  // a mixture's inputs: its node program's outputs

// How light is softened towards the terminator where a normal map tilts the normal, as Cycles does:
// Blender 3.x to 4.2 after Chiang et al. 2019 ("Taming the Shadow Terminator"), later versions after
// Conty Estevez et al. 2019 (a GGX shadowing term, which also refuses light from the far side of the
// smooth normal for every lobe). Evaluated in shading/closure.cpp.
enum class BumpSoftening : uint8_t { None, Chiang, ContyEstevez };

struct SurfacePoint {
  Vec3 ng;       // geometric normal, outward as the primitive defines it
  Vec3 ns;       // shading normal, same hemisphere as ng
  Color albedo;  // base colour, texture applied (single-kind materials)
  // With a normal map: the interpolated normal before it (Cycles' smooth normal, from which its
  // terminator softening measures); zero without one.
  Vec3 smooth_normal{0.0};
  BumpSoftening softening = BumpSoftening::None;
  Vec3 tangent{0.0};      // a mesh's tangent (anisotropic lobes); zero: none
  // A mixture's inputs here (Material::inputs; lobe.h's InputRef); left unset for other materials,
  // which read none (filling them would cost every photon bounce).
  std::array<Vec3f, kMaxInputs> inputs;
};

struct BsdfSample {
  Vec3 wi;
  Color weight;           // f * |cos| / pdf
  bool specular = false;  // a delta lobe was sampled
  uint8_t ray_kind = 0;   // the RayKind of the scattered ray; 0: the ray goes on as it was (transparency)
  int8_t lobe = -1;       // the mixture's lobe it was drawn from (closure_followed_branches)
};

// Below this roughness a surface is treated as perfectly smooth: the eye pass
// follows it and photons pass it without depositing.
constexpr double kSmoothRoughness = 1e-3;

}  // namespace ppm
