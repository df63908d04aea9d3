// Blender's gradient (Perlin) noise in 1 to 4 dimensions, its fractal sums and the Noise and White
// Noise textures, as Cycles computes them in float. Blender 3.x's Noise texture sums unsigned noise
// with octaves doubling in frequency; from 4.1 the node sums signed noise with a lacunarity and,
// besides fBM, offers the former Musgrave texture's types (Legacy below means the 3.x form).
#pragma once

#include "math/types.h"

namespace ppm::textures {

enum class NoiseType : uint8_t { Fbm, Multifractal, HybridMultifractal, RidgedMultifractal, HeteroTerrain };

// Signed Perlin noise of Cycles (about [-1, 1]) at a point of 1 to 4 dimensions.
float snoise(float p);
float snoise(const Vec2f& p);
float snoise(const Vec3f& p);
float snoise(const glm::vec4& p);

struct NoiseSettings {
  int dimensions = 3;
  NoiseType type = NoiseType::Fbm;
  bool normalize = true;  // fBM only: mapped to about [0, 1]
  bool legacy = false;    // Blender 3.x's Noise texture
  float detail = 2.0f, roughness = 0.5f, lacunarity = 2.0f, offset = 0.0f, gain = 1.0f, distortion = 0.0f;
};

struct NoiseResult {
  float fac = 0.0f;
  Vec3f color{0.0f};
};

// The Noise texture at p (already times Scale; w too; 1-D: (w, 0, 0, 0), 2-D and 3-D: the vector,
// 4-D: (vector, w)), its Color only when `with_color`.
NoiseResult noise_texture(const NoiseSettings& s, const glm::vec4& p, bool with_color);

// Blender 3.x's Musgrave texture at p (times Scale; its layout as noise_texture's): its types'
// older sums (octaves in `detail`, exclusive of the last; its Dimension H in `roughness`, each octave
// weighted lacunarity^-H), which 4.1's Noise types replaced.
float musgrave_texture(const NoiseSettings& s, glm::vec4 p);

// Blender 3.x and 4.x's fractal sum of unsigned noise used by the Wave texture's distortion.
float fractal_noise_legacy(const Vec3f& p, float detail, float roughness);
// 4.x's fBM (signed noise, lacunarity, normalised to about [0, 1] when `normalize`).
float fractal_noise_fbm(const Vec3f& p, float detail, float roughness, float lacunarity, bool normalize);

struct WhiteNoiseResult {
  float value = 0.0f;
  Vec3f color{0.0f};
};
WhiteNoiseResult white_noise(int dimensions, const glm::vec4& p);

}  // namespace ppm::textures
