// A dense grid of voxels over an object's texture space: a smoke domain's density, colour, flame,
// heat or temperature, as Blender's fluid simulation hands them over (x fastest, then y, then z).
// Voxel (i, j, k) is the value at the centre of its cell, Generated ((i + 0.5) / nx, ...); between
// centres the grid is trilinear, and cells outside it hold 0, as Cycles' grids do (a sparse grid's
// background), so a domain's values fade to 0 over the half cell at its faces.
#pragma once

#include "math/types.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ppm {

class VoxelGrid {
 public:
  // `values`: nx * ny * nz * channels floats (channels 1, 3 or 4: RGBA's alpha is kept apart).
  // NaN and infinite values are stored as 0 and counted; negative ones are kept (a density's
  // negative values count as 0 where a medium reads it, as Cycles clamps them).
  VoxelGrid(std::array<int, 3> size, int channels, const float* values);

  std::array<int, 3> size() const { return size_; }
  int channels() const { return channels_; }
  size_t voxels() const { return static_cast<size_t>(size_[0]) * size_[1] * size_[2]; }
  size_t not_finite() const { return not_finite_; }
  // The largest value a lookup can give in any colour channel (its mean included), and in alpha.
  float max_value() const { return max_value_; }
  float max_alpha() const { return max_alpha_; }
  size_t memory_bytes() const { return values_.capacity() * sizeof(float); }

  // The colour (a one-channel grid's value in all three) and alpha (1 without one) at Generated `p`.
  glm::vec4 lookup(const Vec3f& p) const;

 private:
  glm::vec4 voxel(int i, int j, int k) const;

  std::array<int, 3> size_{};
  int channels_ = 1;
  std::vector<float> values_;
  size_t not_finite_ = 0;
  float max_value_ = 0.0f, max_alpha_ = 1.0f;
};

// Checks a grid's shape before it is built; throws std::invalid_argument naming `what`.
void check_grid_shape(std::array<long long, 3> size, int channels, const std::string& what);

}  // namespace ppm
