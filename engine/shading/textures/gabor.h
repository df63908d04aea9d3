// Blender's Gabor Texture (4.3 and later) as Cycles computes it in float: sparse convolution noise
// (Tavernier et al. 2019, "Making Gabor Noise Fast and Normalized") of 8 impulses per unit cell,
// each a Gaussian windowed to the unit disc times a complex sinusoid (a phasor, as in Tricard et
// al.'s phasor noise), its orientation the node's turned at random by (1 - anisotropy), its sign
// random. Value is the phasor's imaginary part, Phase its angle and Intensity its length, the first
// and last normalised by six standard deviations of the noise.
#pragma once

#include "math/types.h"

namespace ppm::textures {

struct GaborResult {
  float value = 0.0f, phase = 0.0f, intensity = 0.0f;
};

// `p`: the node's vector times its Scale; `orientation_2d` an angle (radians), `orientation_3d` a
// direction (normalised here).
GaborResult gabor(bool three_d, const Vec3f& p, float frequency, float anisotropy, float orientation_2d,
                  const Vec3f& orientation_3d);

}  // namespace ppm::textures
