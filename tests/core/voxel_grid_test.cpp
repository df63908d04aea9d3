// Tests for voxel grids (a smoke domain's): values at cell centres, trilinear between them, zero
// outside, NaN stored as 0, the largest value; and the node program's grid instruction reading an
// object's grid by slot, its bound and a missing grid's 0 or 1.
#include "shading/voxel_grid.h"

#include "math/rng.h"
#include "shading/node_program.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

namespace {

using namespace ppm;

// A 4 x 3 x 2 grid whose voxel (i, j, k) holds i + 10 j + 100 k.
VoxelGrid ramp_grid() {
  std::vector<float> v;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) v.push_back(float(i + 10 * j + 100 * k));
  return VoxelGrid({4, 3, 2}, 1, v.data());
}

Vec3f centre(int i, int j, int k) { return Vec3f((i + 0.5f) / 4, (j + 0.5f) / 3, (k + 0.5f) / 2); }

TEST(VoxelGrid, HoldsEachVoxelAtItsCellCentreXFastest) {
  const VoxelGrid g = ramp_grid();
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(g.lookup(centre(i, j, k)).x, float(i + 10 * j + 100 * k));
  EXPECT_FLOAT_EQ(g.max_value(), 3 + 20 + 100);
}

TEST(VoxelGrid, IsTrilinearBetweenCentres) {
  const VoxelGrid g = ramp_grid();
  const Vec3f p = centre(1, 1, 0) + Vec3f(0.25f / 4, 0.5f / 3, 0.5f / 2);  // a quarter, a half, a half on
  EXPECT_NEAR(g.lookup(p).x, 1.25f + 15.0f + 50.0f, 1e-4);
}

TEST(VoxelGrid, FadesToZeroOverTheHalfCellOutsideAndIsZeroBeyond) {
  const VoxelGrid g = ramp_grid();
  EXPECT_NEAR(g.lookup(Vec3f(1.0f, centre(3, 2, 1).y, centre(3, 2, 1).z)).x, 0.5f * 123.0f, 1e-3);
  EXPECT_EQ(g.lookup(Vec3f(1.2f, 0.5f, 0.5f)).x, 0.0f);
  EXPECT_EQ(g.lookup(Vec3f(-0.5f, 0.5f, 0.5f)).x, 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(g.lookup(Vec3f(nan, 0.5f, 0.5f)).x, 0.0f);
  EXPECT_EQ(g.lookup(Vec3f(std::numeric_limits<float>::infinity())).x, 0.0f);
}

TEST(VoxelGrid, StoresValuesThatAreNotFiniteAsZeroAndCountsThem) {
  const float v[4] = {1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 2.0f};
  const VoxelGrid g({4, 1, 1}, 1, v);
  EXPECT_EQ(g.not_finite(), 2u);
  EXPECT_FLOAT_EQ(g.lookup(Vec3f(0.375f, 0.5f, 0.5f)).x, 0.0f);
  EXPECT_FLOAT_EQ(g.max_value(), 2.0f);
}

TEST(VoxelGrid, KeepsColourAndAlphaApart) {
  const float v[8] = {0.2f, 0.4f, 0.6f, 0.5f, 1.0f, 0.0f, 0.0f, 3.0f};
  const VoxelGrid g({2, 1, 1}, 4, v);
  const glm::vec4 c = g.lookup(Vec3f(0.25f, 0.5f, 0.5f));
  EXPECT_FLOAT_EQ(c.y, 0.4f);
  EXPECT_FLOAT_EQ(c.w, 0.5f);
  EXPECT_FLOAT_EQ(g.max_value(), 1.0f);
  EXPECT_FLOAT_EQ(g.max_alpha(), 3.0f);
}

TEST(VoxelGrid, RefusesShapesItCannotHold) {
  EXPECT_THROW(check_grid_shape({0, 1, 1}, 1, "g"), std::invalid_argument);
  EXPECT_THROW(check_grid_shape({4, 4, 4}, 2, "g"), std::invalid_argument);
  EXPECT_THROW(check_grid_shape({8192, 8192, 8192}, 1, "g"), std::invalid_argument);
  EXPECT_NO_THROW(check_grid_shape({256, 256, 256}, 4, "g"));
}

TEST(VoxelGrid, StoresNoBrickOfAnEmptyPart) {
  std::vector<float> v(20 * 8 * 8, 0.0f);
  v[19] = 1.0f;  // voxel (19, 0, 0): the third brick along x
  const VoxelGrid g({20, 8, 8}, 1, v.data());
  EXPECT_EQ(g.bricks(), 1u);
  EXPECT_FLOAT_EQ(g.lookup(Vec3f(19.5f / 20, 0.5f / 8, 0.5f / 8)).x, 1.0f);
  EXPECT_EQ(g.lookup(Vec3f(2.5f / 20, 0.5f / 8, 0.5f / 8)).x, 0.0f);
}

// A grid holds its bricks' values and little else: no slack from growing its arrays (a 256^3 smoke
// domain took 1.6 times its bricks before), within 2% of them plus a block table per 128^3 block.
TEST(VoxelGrid, CostsItsBricksWithoutSlack) {
  const int n = 136;  // 17^3 bricks, 2^3 blocks
  std::vector<float> values(size_t(n) * n * n, 1.0f);
  const VoxelGrid dense({n, n, n}, 1, values.data());
  const size_t bricks = size_t(17 * 17 * 17), blocks = 8;
  EXPECT_EQ(dense.bricks(), bricks);
  EXPECT_EQ(dense.blocks(), blocks);
  const double floor = double(bricks) * VoxelGrid::kBrickVoxels * sizeof(float);
  EXPECT_LE(double(dense.memory_bytes()), 1.02 * floor + double(blocks) * VoxelGrid::kBlockPlaces * sizeof(int32_t));
  std::vector<float> sparse_values(bricks * VoxelGrid::kBrickVoxels, 2.0f);
  std::vector<VoxelGrid::Coord> origins, constant_origins;
  for (size_t b = 0; b < bricks; ++b) origins.push_back({int(b % 17) * 8, int(b / 17 % 17) * 8, int(b / 289) * 8});
  for (int t = 0; t < 100; ++t) constant_origins.push_back({8 * t, 400, 0});
  const std::vector<float> constants(100, 3.0f);
  const VoxelGrid sparse(1, Mat4(1.0), origins, sparse_values.data(), constant_origins, constants.data(), "g");
  EXPECT_LE(double(sparse.memory_bytes()), 1.02 * floor + double(sparse.blocks()) * VoxelGrid::kBlockPlaces * 4 + 4096);
}

// A sparse grid: a brick at index (-8, 0, 16) holding its voxel's z (z fastest, OpenVDB's leaf
// order), a constant brick of 5 beside it along x, index space = object space times 2.
VoxelGrid sparse_grid() {
  std::vector<float> brick(VoxelGrid::kBrickVoxels);
  for (int o = 0; o < VoxelGrid::kBrickVoxels; ++o) brick[o] = float(o % 8);
  const float constant = 5.0f;
  return VoxelGrid(1, Mat4(glm::scale(glm::dmat4(1.0), glm::dvec3(2.0))), {{-8, 0, 16}}, brick.data(), {{0, 0, 16}},
                   &constant, "test");
}

TEST(VoxelGrid, ReadsBricksAtTheirOriginsZFastestAndConstantsAsTiles) {
  const VoxelGrid g = sparse_grid();
  EXPECT_FLOAT_EQ(g.lookup(Vec3f(-3.0f, 1.0f, 9.5f)).x, 3.0f);   // index (-6, 2, 19): z 19 - 16
  EXPECT_FLOAT_EQ(g.lookup(Vec3f(2.0f, 1.0f, 10.0f)).x, 5.0f);   // index (4, 2, 20): the constant
  EXPECT_FLOAT_EQ(g.lookup(Vec3f(-0.25f, 1.0f, 9.5f)).x, 4.0f);  // index -0.5: half of 3 and of 5
  EXPECT_EQ(g.lookup(Vec3f(-3.0f, 1.0f, 0.0f)).x, 0.0f);         // no brick there
  const auto lo = g.index_lo(), hi = g.index_hi();
  EXPECT_EQ(lo[0], -8);
  EXPECT_EQ(hi[2], 24);
  EXPECT_FLOAT_EQ(g.max_value(), 7.0f);
}

TEST(VoxelGrid, TwoBricksFarApartCostTheirBlocksNotTheirBox) {
  std::vector<float> two(2 * VoxelGrid::kBrickVoxels, 0.0f);
  two[5] = 2.0f, two[VoxelGrid::kBrickVoxels + 7] = 3.0f;  // voxel (0, 0, 5) of each brick
  const VoxelGrid g(1, Mat4(1.0), {{0, 0, 0}, {-4000, 4000, 4000}}, two.data(), {}, nullptr, "g");
  EXPECT_LT(g.memory_bytes(), 1024u * 1024);  // (a table of every brick place in their box: 503 MB)
  EXPECT_FLOAT_EQ(g.lookup(Vec3f(0.0f, 0.0f, 5.0f)).x, 2.0f);
  EXPECT_FLOAT_EQ(g.lookup(Vec3f(-4000.0f, 4000.0f, 4007.0f)).x, 3.0f);
  EXPECT_EQ(g.lookup(Vec3f(-2000.0f, 2000.0f, 2000.0f)).x, 0.0f);
}

// max_in bounds every lookup at points of its box, trilinear or stochastic (up to float rounding:
// the trilinear mix of equal values may exceed them by an ulp), and is 0 away from the bricks: the
// sparse grid (a brick of 0-7 by z, a constant 5) under random boxes of every size.
TEST(VoxelGrid, ItsLargestValueInABoxBoundsEveryLookupThere) {
  VoxelGrid g = sparse_grid();
  Rng rng(31, 0, 0);
  int tight = 0;
  for (int box = 0; box < 400; ++box) {
    const Vec3 centre(-6.0 + 10.0 * rng.uniform(), -2.0 + 6.0 * rng.uniform(), 6.0 + 8.0 * rng.uniform());
    const Vec3 half = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * (box % 2 ? 0.3 : 3.0);
    const float bound = g.max_in(centre - half, centre + half);
    ASSERT_LE(bound, g.max_value());
    uint32_t state = 7;
    for (int i = 0; i < 300; ++i) {
      const Vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
      const Vec3f p(centre - half + 2.0 * half * u);
      g.set_stochastic(i % 2 == 1);
      const float v = g.lookup(p, &state).x;
      ASSERT_LE(v, bound * (1.0f + 1e-6f)) << "at (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
    tight += bound < g.max_value();
  }
  EXPECT_GT(tight, 100);  // many boxes miss the brick's 7s or all bricks
  EXPECT_EQ(g.max_in(Vec3(-3.0, 1.0, -2.0), Vec3(-2.0, 2.0, 0.0)), 0.0f);  // no brick near
  EXPECT_FLOAT_EQ(g.max_in(Vec3(2.0, 1.0, 10.0), Vec3(2.5, 1.5, 10.5)), 5.0f);  // inside the constant
  EXPECT_EQ(g.max_in(Vec3(std::nan(""), 0.0, 0.0), Vec3(1.0)), g.max_value());  // not a box: everything
}

TEST(VoxelGrid, ItsLargestValueInABoxSkipsEmptyBlocks) {
  std::vector<float> two(2 * VoxelGrid::kBrickVoxels, 0.0f);
  two[5] = 2.0f, two[VoxelGrid::kBrickVoxels + 7] = 3.0f;
  const VoxelGrid g(1, Mat4(1.0), {{0, 0, 0}, {-4000, 4000, 4000}}, two.data(), {}, nullptr, "g");
  EXPECT_FLOAT_EQ(g.max_in(Vec3(-1.0), Vec3(8.0)), 2.0f);
  EXPECT_FLOAT_EQ(g.max_in(Vec3(-4010.0, 3990.0, 3990.0), Vec3(-3990.0, 4010.0, 4010.0)), 3.0f);
  EXPECT_EQ(g.max_in(Vec3(-3000.0, 1000.0, 1000.0), Vec3(-1000.0, 3000.0, 3000.0)), 0.0f);
  EXPECT_FLOAT_EQ(g.max_in(Vec3(-1e9), Vec3(1e9)), 3.0f);  // the whole box, block by block
}

TEST(VoxelGrid, RefusesBricksOffTheirPlacesAndTransformsThatAreNotFinite) {
  const float v[VoxelGrid::kBrickVoxels] = {};
  EXPECT_THROW(VoxelGrid(1, Mat4(1.0), {{3, 0, 0}}, v, {}, nullptr, "g"), std::invalid_argument);
  Mat4 bad(1.0);
  bad[3][0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(VoxelGrid(1, bad, {{0, 0, 0}}, v, {}, nullptr, "g"), std::invalid_argument);
  const std::vector<float> two(2 * VoxelGrid::kBrickVoxels, 0.0f);
  EXPECT_THROW(VoxelGrid(1, Mat4(1.0), {{0, 0, 0}, {80000, 80000, 80000}}, two.data(), {}, nullptr, "g"),
               std::invalid_argument);  // the table would be too large
}

TEST(VoxelGrid, AStochasticLookupPicksVoxelsByTheTrilinearWeights) {
  VoxelGrid g = ramp_grid();
  g.set_stochastic(true);
  const Vec3f p = centre(1, 1, 0) + Vec3f(0.25f / 4, 0.5f / 3, 0.5f / 2);  // as IsTrilinearBetweenCentres
  uint32_t state = 12345u;
  double sum = 0.0, sum4 = 0.0;
  const int n = 200000;
  for (int k = 0; k < n; ++k) {
    const float v = g.lookup(p, &state).x;
    const int i = int(v) % 10, j = (int(v) / 10) % 10, kk = int(v) / 100;  // a voxel's own value
    ASSERT_EQ(v, float(i + 10 * j + 100 * kk));
    sum += v, sum4 += std::pow(double(v), 4);
  }
  EXPECT_NEAR(sum / n, 1.25 + 15.0 + 50.0, 0.5);  // the trilinear value, in the mean
  EXPECT_GT(sum4 / n, 1.1 * std::pow(66.25, 4));  // and a nonlinear function of it averages voxels
  EXPECT_NEAR(g.lookup(p).x, 66.25f, 1e-3);        // without a state: trilinear
}

// Generated -> the grid in slot 0, its fac the program's output.
NodeProgram grid_program(bool missing_is_one) {
  NodeProgram p;
  p.registers = 5;
  NodeInstruction coord;
  coord.op = NodeOp::Coord;
  coord.mode = static_cast<uint8_t>(CoordKind::Generated);
  coord.out = {1, 0, 0};
  NodeInstruction grid;
  grid.op = NodeOp::Grid;
  grid.in[0] = 1;
  grid.out = {2, 3, 4};
  grid.flags = missing_is_one ? 1 : 0;
  p.code = {coord, grid};
  p.outputs = {3};
  return p;
}

TEST(GridInstruction, ReadsTheObjectsGridAtGeneratedAndIsBoundedByItsLargestValue) {
  ObjectInfo object;  // texture space [-1, 1]^3
  object.grids.push_back(std::make_shared<const VoxelGrid>(ramp_grid()));
  const NodeProgram p = grid_program(true);
  p.validate(0, "test");
  ShadingContext c;
  c.object = &object;
  const Vec3f g = centre(2, 1, 1);
  c.position = Vec3(-1.0 + 2.0 * g.x, -1.0 + 2.0 * g.y, -1.0 + 2.0 * g.z);
  Vec3f out[1];
  p.run(c, {}, out);
  EXPECT_NEAR(out[0].x, 112.0f, 1e-3);
  EXPECT_DOUBLE_EQ(p.output_bound(0, {}, &object), 123.0);
  EXPECT_FALSE(p.output_bound(0, {}) < std::numeric_limits<double>::infinity());  // no object: unknown
}

// With a region, a grid read at the Object or Generated coordinate is bounded by its largest value
// there; read at another (Position, or anything computed), by its largest value anywhere.
TEST(GridInstruction, IsBoundedInARegionWhereItReadsTheObjectCoordinate) {
  ObjectInfo object;
  object.world_to_object = Mat4(glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.0, -10.0)));  // world z 10: object 0
  object.grids.push_back(std::make_shared<const VoxelGrid>(sparse_grid()));
  NodeProgram p = grid_program(false);
  p.code[0].mode = static_cast<uint8_t>(CoordKind::Object);
  p.outputs = {2};  // the colour
  p.validate(0, "test");
  const Aabb near_constant{Vec3(2.0, 1.0, 20.0), Vec3(2.5, 1.5, 20.5)}, empty{Vec3(-3.0, 1.0, 8.0), Vec3(-2.0, 2.0, 9.0)};
  EXPECT_FLOAT_EQ(p.output_bound(0, {}, &object, &near_constant), 5.0);
  EXPECT_EQ(p.output_bound(0, {}, &object, &empty), 0.0);
  EXPECT_FLOAT_EQ(p.output_bound(0, {}, &object), 7.0);
  p.code[0].mode = static_cast<uint8_t>(CoordKind::Generated);  // (object + 1) / 2 here: near nothing either
  EXPECT_EQ(p.output_bound(0, {}, &object, &empty), 0.0);
  p.code[0].mode = static_cast<uint8_t>(CoordKind::Position);
  EXPECT_FLOAT_EQ(p.output_bound(0, {}, &object, &empty), 7.0);
}

TEST(GridInstruction, AnObjectWithoutTheGridReadsZeroOrWithFlagOneOne) {
  const ObjectInfo none;
  ShadingContext c;
  c.object = &none;
  Vec3f out[1];
  grid_program(false).run(c, {}, out);
  EXPECT_EQ(out[0].x, 0.0f);
  EXPECT_DOUBLE_EQ(grid_program(false).output_bound(0, {}, &none), 0.0);
  grid_program(true).run(c, {}, out);
  EXPECT_EQ(out[0].x, 1.0f);
  EXPECT_DOUBLE_EQ(grid_program(true).output_bound(0, {}, &none), 1.0);
}

TEST(GridInstruction, AnUnknownFlagIsRefused) {
  NodeProgram p = grid_program(false);
  p.code[1].flags = 2;
  EXPECT_THROW(p.validate(0, "test"), std::invalid_argument);
}

}  // namespace
