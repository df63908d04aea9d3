// A majorant grid: a medium's bound on its extinction per cell of a coarse grid over its box, so
// that the trackers (free_path.h's track_segment_pieces) draw tentative collisions at the rate of
// the cell they are in, not at the densest voxel's everywhere: a smoke domain or an OpenVDB cloud is
// mostly empty space, where a single majorant spends its steps on null collisions.
//
// Cells are roughly cubic, at most kMaxCells along the box's longest side. Each cell's value is what
// the caller bounds over the cell's box widened by kCellMargin of a cell on each side, so that a
// point the walk files in a neighbouring cell by rounding is still bounded. Outside the box the
// walk gives `outside` (the medium's bound everywhere).
#pragma once

#include "geometry/ray.h"
#include "math/aabb.h"
#include "math/types.h"
#include "shading/free_path.h"

#include <array>
#include <cstdint>
#include <vector>

namespace ppm {

class MajorantGrid {
 public:
  static constexpr int kMaxCells = 32;
  static constexpr double kCellMargin = 1.0 / 16.0;

  struct Cell {
    float majorant = 0.0f;  // rounded up from the bound
    bool emits = false;     // the medium may emit there
  };
  // `bound(Aabb)`: the Cell for a box (its majorant >= the medium's largest sigma_t there).
  template <class Bound>
  MajorantGrid(const Aabb& box, const Cell& outside, Bound&& bound) : box_(box), outside_(outside) {
    const Vec3 e = box.extent();
    const double longest = std::max({e.x, e.y, e.z});
    for (int a = 0; a < 3; ++a) {
      dims_[a] = longest > 0.0 ? std::clamp(int(std::ceil(kMaxCells * e[a] / longest - 1e-9)), 1, kMaxCells) : 1;
      cell_[a] = e[a] / dims_[a];
    }
    cells_.resize(size_t(dims_[0]) * dims_[1] * dims_[2]);
    for (int z = 0; z < dims_[2]; ++z)
      for (int y = 0; y < dims_[1]; ++y)
        for (int x = 0; x < dims_[0]; ++x) {
          Aabb c;
          c.lo = box.lo + Vec3(x - kCellMargin, y - kCellMargin, z - kCellMargin) * cell_;
          c.hi = box.lo + Vec3(x + 1 + kCellMargin, y + 1 + kCellMargin, z + 1 + kCellMargin) * cell_;
          cells_[index(x, y, z)] = bound(c);
        }
  }

  std::array<int, 3> dims() const { return dims_; }
  const Cell& outside() const { return outside_; }
  // The cells' mean majorant over the box's volume (to tell whether the grid pays).
  double mean_majorant() const;

  // The cells along ray.origin + t ray.direction, t from 0 on: pieces [previous end, end) with
  // the cell's majorant and whether it emits; before and after the box the outside's, the last
  // piece's end infinite. At most the sum of the dims plus 3 pieces.
  struct Piece {
    double end;
    const Cell* cell;
  };
  class Walk {
   public:
    Walk() = default;
    Walk(const MajorantGrid& grid, const Ray& ray);
    Piece next();

   private:
    const MajorantGrid* grid_ = nullptr;
    std::array<int, 3> at_{}, step_{};
    Vec3 t_next_{kInf}, t_delta_{kInf};
    double t_enter_ = kInf, t_leave_ = kInf, t_ = 0.0;
    int stage_ = 0;  // 0: before the box, 1: in it, 2: after
  };
  Walk walk(const Ray& ray) const { return Walk(*this, ray); }

 private:
  size_t index(int x, int y, int z) const { return (size_t(z) * dims_[1] + size_t(y)) * dims_[0] + size_t(x); }
  Aabb box_;
  Cell outside_;
  std::array<int, 3> dims_{1, 1, 1};
  Vec3 cell_{1.0};
  std::vector<Cell> cells_;
};

}  // namespace ppm
