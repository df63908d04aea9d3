// A grid of voxels: a smoke domain's density, colour, flame, heat or temperature (dense, over the
// object's texture space), or an OpenVDB grid's (sparse, in its own index space). Both are kept as
// bricks of 8^3 voxels (an OpenVDB leaf), an empty brick not stored; tables of 16^3 brick places (a
// block of 128^3 voxels, an OpenVDB lower node), kept only for blocks that hold something and found
// through a table over the blocks' box, say which brick, constant (an OpenVDB tile) or nothing (0)
// covers each place: two clouds far apart cost their bricks, blocks and 4 bytes per block of their
// box (two leaves 4000 voxels apart: 0.17 MB, where a table of every brick place took 503 MB). Voxel
// centres lie at integer index coordinates; between them the grid is trilinear, and outside its
// bricks it is 0, as Cycles' grids are (a sparse grid's background), so values fade to 0 over the
// half voxel beyond.
#pragma once

#include "math/types.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ppm {

class VoxelGrid {
 public:
  static constexpr int kBrick = 8;                            // voxels along a brick's edge
  static constexpr int kBrickVoxels = kBrick * kBrick * kBrick;
  static constexpr int kBlock = 16;                           // brick places along a block's edge
  static constexpr int kBlockPlaces = kBlock * kBlock * kBlock;
  using Coord = std::array<int, 3>;

  // A dense grid: `values` nx * ny * nz * channels floats, x fastest (a smoke domain's); `to_index`
  // maps the instruction's input to index space (default: [0, 1]^3 onto the grid, voxel (i, j, k) at
  // ((i + 0.5) / nx, ...), as a smoke domain's grid over Generated).
  VoxelGrid(Coord size, int channels, const float* values);
  VoxelGrid(Coord size, int channels, const float* values, const Mat4& to_index);
  // A sparse grid: bricks whose first voxels lie at `origins` (index coordinates, multiples of
  // kBrick), `values` kBrick^3 * channels floats each with z fastest (OpenVDB's leaf order); constant
  // bricks at `constant_origins`, `channels` floats each; `to_index` maps the instruction's input
  // (object space) to index space. Throws std::invalid_argument naming `what` for what it cannot hold.
  VoxelGrid(int channels, const Mat4& to_index, const std::vector<Coord>& origins, const float* values,
            const std::vector<Coord>& constant_origins, const float* constant_values, const std::string& what);

  int channels() const { return channels_; }
  size_t bricks() const { return bricks_; }
  size_t blocks() const { return places_.size() / kBlockPlaces; }  // blocks of 128^3 voxels holding something
  // Regions of 4096^3 voxels (32^3 blocks, aligned as OpenVDB's upper nodes) holding something.
  size_t regions_4096() const;
  size_t not_finite() const { return not_finite_; }
  // The largest value a lookup can give in any colour channel (its mean included), and in alpha.
  float max_value() const { return max_value_; }
  float max_alpha() const { return max_alpha_; }
  // The largest value a lookup (trilinear or stochastic) can give in any colour channel at a point
  // of the box [lo, hi] of its input space: the largest of the bricks its voxels' neighbours lie in
  // (a majorant grid's cell, scene/majorant_grid.h). max_value() where the box is not finite.
  float max_in(const Vec3& lo, const Vec3& hi) const;
  size_t memory_bytes() const {
    return (values_.capacity() + brick_max_.capacity()) * sizeof(float) +
           (blocks_.capacity() + places_.capacity()) * sizeof(int32_t);
  }
  // The box of index coordinates the bricks cover (lo inclusive, hi exclusive).
  Coord index_lo() const { return lo_; }
  Coord index_hi() const { return hi_; }

  // The colour (a one-channel grid's value in all three) and alpha (1 without one) at `p`. A
  // stochastic grid given an LCG `state` returns one voxel, picked along each axis with the
  // trilinear weight (Cycles 5.0's volume attributes: the mean is the interpolation's, and a
  // nonlinear function of it, a blackbody's T^4, averages over voxels as Cycles'); else trilinear.
  glm::vec4 lookup(const Vec3f& p, uint32_t* state = nullptr) const;
  void set_stochastic(bool on) { stochastic_ = on; }
  bool stochastic() const { return stochastic_; }

 private:
  void make_table(const std::vector<Coord>& origins, const std::vector<Coord>& constant_origins,
                  const std::string& what);
  void store(float* v, size_t count, bool alpha_last);
  glm::vec4 voxel(int i, int j, int k) const;
  int32_t block_at(int x, int y, int z) const;  // block (x, y, z)'s table entry; -1 outside the table

  int channels_ = 1;
  glm::mat4 to_index_{1.0f};
  Coord lo_{}, hi_{};             // the bricks' box, in voxels
  Coord block_lo_{}, block_dims_{};  // the block table's box, in blocks
  std::vector<int32_t> blocks_;   // per block: its places' offset / kBlockPlaces, or -1 (nothing there)
  std::vector<int32_t> places_;   // per brick place: >= 0 a stored brick, -1 nothing, <= -2 constant -2 - k
  std::vector<float> values_;     // the stored bricks, then the constants
  std::vector<float> brick_max_;  // per stored brick, then per constant: its largest colour value
  size_t bricks_ = 0, constants_at_ = 0;
  size_t not_finite_ = 0;
  float max_value_ = 0.0f, max_alpha_ = 1.0f;
  bool stochastic_ = false;
};

// Checks a dense grid's shape before it is built; throws std::invalid_argument naming `what`.
void check_grid_shape(std::array<long long, 3> size, int channels, const std::string& what);

}  // namespace ppm
