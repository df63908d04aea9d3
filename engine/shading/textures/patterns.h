// Blender's pattern textures as Cycles computes them in float: Checker, Gradient, Wave, Magic and
// Brick. Each takes the node's vector already multiplied by its Scale, except Gradient (which has
// none) and Magic (whose newest form wraps the unscaled vector first).
#pragma once

#include "math/types.h"

namespace ppm::textures {

// 1 on the cells of one colour, 0 on the other.
float checker(Vec3f p);

enum class GradientType : uint8_t { Linear, Quadratic, Easing, Diagonal, Radial, QuadraticSphere, Spherical };
float gradient(GradientType type, const Vec3f& p);  // in [0, 1]

struct WaveSettings {
  uint8_t kind = 0;       // 0 bands, 1 rings
  uint8_t direction = 0;  // bands: x, y, z, diagonal; rings: x, y, z, spherical
  uint8_t profile = 0;    // 0 sine, 1 saw, 2 triangle
  bool legacy = false;    // Blender 3.x's distortion noise
  float distortion = 0.0f, detail = 2.0f, detail_scale = 1.0f, detail_roughness = 0.5f, phase = 0.0f;
};
float wave(const WaveSettings& s, Vec3f p);

// `wrapped`: the newest Blender's form, which wraps the unscaled vector to [0, 2 pi) first.
Vec3f magic(const Vec3f& vector, float scale, int depth, float distortion, bool wrapped);

struct BrickSettings {
  float offset = 0.5f, squash = 1.0f;
  int offset_frequency = 2, squash_frequency = 2;
  float mortar_size = 0.02f, mortar_smooth = 0.1f, bias = 0.0f, brick_width = 0.5f, row_height = 0.25f;
};
struct BrickResult {
  float tint = 0.0f, mortar = 0.0f;
};
BrickResult brick(const BrickSettings& s, const Vec3f& p);

}  // namespace ppm::textures
