// Majorant grids (shading/majorant_grid.h): cells that hold their box's bound, and a walk along a
// ray whose pieces tile t >= 0 in order, each piece inside the cell it names (the box's outside
// before and after it), from inside and outside the box, along axes and at grazing angles.
#include "shading/majorant_grid.h"

#include "math/rng.h"
#include "math/sampling.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ppm {
namespace {

// A grid over [-1, 3] x [0, 1] x [0, 2] whose cells' majorants encode their cell's index.
MajorantGrid numbered_grid(const Aabb& box) {
  return MajorantGrid(box, MajorantGrid::Cell{-1.0f, true}, [&](const Aabb& c) {
    const Vec3 mid = c.center();
    return MajorantGrid::Cell{float(mid.x * 1000.0 + mid.y * 100.0 + mid.z), false};
  });
}

TEST(MajorantGrid, CellsAreRoughlyCubicUpToTheLongestSide) {
  const MajorantGrid g = numbered_grid(Aabb{Vec3(-1.0, 0.0, 0.0), Vec3(3.0, 1.0, 2.0)});
  EXPECT_EQ(g.dims()[0], MajorantGrid::kMaxCells);
  EXPECT_EQ(g.dims()[1], MajorantGrid::kMaxCells / 4);
  EXPECT_EQ(g.dims()[2], MajorantGrid::kMaxCells / 2);
  const MajorantGrid flat = numbered_grid(Aabb{Vec3(0.0), Vec3(1.0, 1.0, 0.0)});
  EXPECT_EQ(flat.dims()[2], 1);
}

// Each cell's bound was asked for its box widened by kCellMargin: the centre the bound saw is the
// cell's centre, so the pieces' cells can be checked by where their middle lies.
TEST(MajorantGrid, AWalkTilesTheRayWithTheCellsItCrosses) {
  const Aabb box{Vec3(-1.0, 0.0, 0.0), Vec3(3.0, 1.0, 2.0)};
  const MajorantGrid g = numbered_grid(box);
  const Vec3 size = box.extent() / Vec3(g.dims()[0], g.dims()[1], g.dims()[2]);
  Rng rng(41, 0, 0);
  for (int r = 0; r < 2000; ++r) {
    Ray ray;
    ray.origin = r % 3 == 0 ? box.lo + box.extent() * Vec3(rng.uniform(), rng.uniform(), rng.uniform())
                            : Vec3(-4.0, -3.0, -3.0) + Vec3(10.0, 7.0, 8.0) * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
    ray.direction = sample_uniform_sphere(rng.uniform(), rng.uniform());
    if (r % 5 == 1) ray.direction = Vec3(0.0, 0.0, 1.0);                       // along an axis
    if (r % 5 == 2) ray.direction = glm::normalize(Vec3(1.0, 1e-9, -1e-12));  // grazing
    MajorantGrid::Walk walk = g.walk(ray);
    double start = 0.0;
    int pieces = 0;
    for (;; ++pieces) {
      ASSERT_LT(pieces, g.dims()[0] + g.dims()[1] + g.dims()[2] + 3);
      const MajorantGrid::Piece piece = walk.next();
      ASSERT_GE(piece.end, start);
      if (piece.end == kInf) {
        EXPECT_EQ(piece.cell, &g.outside());
        break;
      }
      if (piece.end - start > 1e-9) {
        const Vec3 mid = ray.origin + 0.5 * (start + piece.end) * ray.direction;
        const bool inside = glm::all(glm::greaterThan(mid, box.lo)) && glm::all(glm::lessThan(mid, box.hi));
        if (piece.cell == &g.outside()) {
          EXPECT_FALSE(inside && glm::all(glm::greaterThan(mid, box.lo + 1e-6)) &&
                       glm::all(glm::lessThan(mid, box.hi - 1e-6)))
              << "the outside's piece inside the box, ray " << r;
        } else {
          ASSERT_TRUE(inside || glm::length(glm::max(box.lo - mid, mid - box.hi)) < 1e-6) << "ray " << r;
          const Vec3 cell = glm::floor((mid - box.lo) / size);
          const Vec3 centre = box.lo + (cell + 0.5) * size;
          const float want = float(centre.x * 1000.0 + centre.y * 100.0 + centre.z);
          const Vec3 off = glm::abs((mid - box.lo) / size - glm::round((mid - box.lo) / size));
          if (glm::all(glm::greaterThan(off, Vec3(1e-6))))  // not on a cell's face
            EXPECT_NEAR(piece.cell->majorant, want, 1e-3) << "ray " << r;
        }
      }
      start = piece.end;
    }
  }
}

TEST(MajorantGrid, ARayMissingTheBoxOrNotFiniteIsOutsideEverywhere) {
  const MajorantGrid g = numbered_grid(Aabb{Vec3(0.0), Vec3(1.0)});
  for (const Ray& ray : {Ray{Vec3(5.0, 5.0, 5.0), Vec3(1.0, 0.0, 0.0)}, Ray{Vec3(2.0, 0.5, 0.5), Vec3(1.0, 0.0, 0.0)},
                         Ray{Vec3(std::nan(""), 0.5, 0.5), Vec3(1.0, 0.0, 0.0)},
                         Ray{Vec3(0.5, 0.5, 0.5), Vec3(std::nan(""), 0.0, 0.0)}}) {
    MajorantGrid::Walk walk = g.walk(ray);
    const MajorantGrid::Piece piece = walk.next();
    EXPECT_EQ(piece.end, kInf);
    EXPECT_EQ(piece.cell, &g.outside());
  }
}

}  // namespace
}  // namespace ppm
