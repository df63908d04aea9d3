// Tests of the hashed uniform grid against brute force, mirroring the
// quantile grid tests (same interface) plus cell-size extremes: cells much
// smaller than the query radius (many cells per box, shared buckets), much
// larger, and bounds that force the cell size up. Every query compares the
// exact set "items within r" found through the index with brute force, and
// checks that point items (and point queries over spheres) are visited once.
#include "ppm/hash_grid.h"

#include "grid_test_helpers.h"
#include "math/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace ppm {
namespace {

using namespace grid_test;

TEST(HashGrid, RandomPointsBoxQueriesMatchBruteForce) {
  const std::vector<Vec3> points = random_points(4000, 2, Vec3(0.0), Vec3(1.0));
  const std::vector<Vec3> queries = random_points(300, 3, Vec3(-0.1), Vec3(1.1));
  const std::vector<double> radii = random_radii(300, 4, 0.005, 0.3);
  // From ~40 cells per query axis (heavy bucket sharing) to one cell overall.
  for (double cell : {0.007, 0.03, 0.1, 2.0}) {
    HashGrid grid;
    grid.build(points, {}, cell);
    EXPECT_EQ(grid.item_count(), points.size());
    EXPECT_EQ(grid.reference_count(), points.size());
    EXPECT_EQ(grid.cell_size(), cell);
    for (size_t q = 0; q < queries.size(); ++q) expect_box_query_exact(grid, points, queries[q], radii[q]);
  }
}

TEST(HashGrid, RelabelledRunsMatchBruteForce) {
  const std::vector<Vec3> points = three_walls(20000, 24);
  const std::vector<Vec3> queries = random_points(150, 26, Vec3(-0.1), Vec3(1.1));
  const std::vector<double> radii = random_radii(150, 27, 0.001, 0.2);
  HashGrid grid;
  expect_run_queries_exact(grid, [](HashGrid& g, const std::vector<Vec3>& p) { g.build(p, {}, 0.03); }, points,
                           queries, radii);
}

TEST(HashGrid, RandomSpheresPointQueriesMatchBruteForce) {
  const std::vector<Vec3> centers = random_points(3000, 5, Vec3(0.0), Vec3(1.0));
  const std::vector<double> radii = random_radii(3000, 6, 0.0, 0.12);
  std::vector<Vec3> queries = random_points(3000, 7, Vec3(-0.1), Vec3(1.1));
  for (size_t i = 0; i < 300; ++i) {
    queries.push_back(centers[i]);
    queries.push_back(centers[i] + Vec3(radii[i], 0.0, 0.0));
    queries.push_back(centers[i] - Vec3(0.0, 0.0, radii[i]));
  }
  for (double cell : {0.02, 0.1, 0.5}) {
    HashGrid grid;
    grid.build(centers, radii, cell);
    EXPECT_GE(grid.reference_count(), centers.size());
    for (const Vec3& p : queries) expect_point_query_exact(grid, centers, radii, p);
    for (size_t q = 0; q < 200; ++q)
      expect_sphere_box_superset(grid, centers, radii, queries[q] - 0.05, queries[q] + 0.05);
  }
}

TEST(HashGrid, PlanarPointsAllXEqual) {
  const size_t n = 100000;
  std::vector<Vec3> points = random_points(n, 8, Vec3(0.0), Vec3(1.0));
  for (Vec3& p : points) p.x = 1.0;
  HashGrid grid;
  grid.build(points, {}, 0.01);
  EXPECT_EQ(grid.reference_count(), n);
  EXPECT_LE(grid.cell_count(), 4 * n);
  EXPECT_LE(grid.nonempty_cell_count(), 100u * 100u);  // one layer of cells
  const std::vector<Vec3> centers = random_points(150, 9, Vec3(0.5, 0.0, 0.0), Vec3(1.5, 1.0, 1.0));
  for (size_t q = 0; q < centers.size(); ++q) {
    expect_box_query_exact(grid, points, centers[q], 0.02 + 0.3 * (q % 7) / 7.0);
    const Vec3& p = points[q * 97];
    expect_box_query_exact(grid, points, Vec3(0.75, p.y, p.z), 0.25);
    expect_box_query_exact(grid, points, Vec3(1.25, p.y, p.z), 0.25);
  }
}

TEST(HashGrid, PlanarSpheresAllXEqual) {
  const size_t n = 50000;
  std::vector<Vec3> centers = random_points(n, 10, Vec3(0.0), Vec3(1.0));
  for (Vec3& c : centers) c.x = 1.0;
  const std::vector<double> radii = random_radii(n, 11, 0.002, 0.01);
  HashGrid grid;
  grid.build(centers, radii, 0.02);
  EXPECT_LE(grid.reference_count(), 4 * n);  // a sphere spans at most 2x2 cells of a wall
  std::vector<Vec3> queries = random_points(2000, 12, Vec3(1.0, 0.0, 0.0), Vec3(1.0, 1.0, 1.0));
  for (size_t i = 0; i < 500; ++i) queries.push_back(centers[i] + Vec3(radii[i], 0.0, 0.0));
  for (const Vec3& p : queries) expect_point_query_exact(grid, centers, radii, p);
}

TEST(HashGrid, ThreeWallsOfABox) {
  const size_t n = 30000;
  const std::vector<Vec3> points = three_walls(n, 13);
  HashGrid grid;
  grid.build(points, {}, 0.02);
  EXPECT_EQ(grid.reference_count(), n);
  const std::vector<Vec3> queries = three_walls(300, 14);
  for (size_t q = 0; q < queries.size(); ++q)
    expect_box_query_exact(grid, points, queries[q], 0.01 + 0.1 * (q % 5) / 5.0);

  const std::vector<double> radii = random_radii(n, 15, 0.002, 0.03);
  grid.build(points, radii, 0.03);
  // Up to 3x3 cells in a wall's plane, and 2 across it where a wall falls on a
  // cell boundary: about 9 references per sphere here.
  EXPECT_LE(grid.reference_count(), 12 * n);
  const std::vector<Vec3> photons = three_walls(3000, 16);
  for (const Vec3& p : photons) expect_point_query_exact(grid, points, radii, p);
  for (size_t i = 0; i < 300; ++i) expect_point_query_exact(grid, points, radii, points[i]);
}

TEST(HashGrid, HeavyDuplicates) {
  const Vec3 p(0.3, 0.6, 0.9);
  const std::vector<Vec3> copies(1000, p);
  HashGrid grid;
  grid.build(copies, {}, 0.01);
  EXPECT_EQ(grid.reference_count(), 1000u);
  EXPECT_EQ(grid.nonempty_cell_count(), 1u);
  expect_box_query_exact(grid, copies, p, 0.0);
  expect_box_query_exact(grid, copies, p + Vec3(0.1, 0.0, 0.0), 0.1);
  expect_box_query_exact(grid, copies, p + Vec3(0.2, 0.0, 0.0), 0.1);

  const std::vector<double> radii(1000, 0.1);
  grid.build(copies, radii, 0.05);
  expect_point_query_exact(grid, copies, radii, p);
  expect_point_query_exact(grid, copies, radii, p + Vec3(0.0, 0.1, 0.0));
  expect_point_query_exact(grid, copies, radii, p + Vec3(0.0, 0.2, 0.0));

  std::vector<Vec3> mixed = random_points(1000, 17, Vec3(0.0), Vec3(1.0));
  mixed.insert(mixed.end(), copies.begin(), copies.end());
  grid.build(mixed, {}, 0.05);
  EXPECT_EQ(grid.reference_count(), mixed.size());
  for (const Vec3& c : random_points(100, 18, Vec3(0.0), Vec3(1.0))) expect_box_query_exact(grid, mixed, c, 0.15);
  expect_box_query_exact(grid, mixed, p, 0.05);
}

TEST(HashGrid, SinglePoint) {
  const std::vector<Vec3> one = {Vec3(2.0, -1.0, 0.5)};
  HashGrid grid;
  grid.build(one, {}, 0.1);
  expect_box_query_exact(grid, one, one[0], 0.0);
  expect_box_query_exact(grid, one, one[0] + Vec3(1.0), 1.0);
  expect_box_query_exact(grid, one, one[0] + Vec3(1.0), 2.0);
  const std::vector<double> radius = {0.5};
  grid.build(one, radius, 0.1);
  expect_point_query_exact(grid, one, radius, one[0]);
  expect_point_query_exact(grid, one, radius, one[0] + Vec3(0.0, 0.5, 0.0));
  expect_point_query_exact(grid, one, radius, one[0] + Vec3(0.0, 0.6, 0.0));
}

TEST(HashGrid, EmptyInput) {
  HashGrid grid;
  const auto check_empty = [&] {
    EXPECT_EQ(grid.item_count(), 0u);
    EXPECT_EQ(grid.reference_count(), 0u);
    size_t visits = 0;
    grid.for_each_candidate_at(Vec3(0.0), [&](uint32_t) { ++visits; });
    grid.for_each_candidate_in_box(Vec3(-1e300), Vec3(1e300), [&](uint32_t) { ++visits; });
    EXPECT_EQ(visits, 0u);
  };
  check_empty();  // never built
  grid.build({}, {}, 0.1);
  check_empty();
  grid.build(random_points(100, 19, Vec3(0.0), Vec3(1.0)), {}, 0.1);
  grid.build({}, {}, 0.1);
  check_empty();
}

TEST(HashGrid, ValuesExactlyOnCellBoundaries) {
  // Integer lattice with unit cells: every coordinate lies on a cell boundary
  // and integer boxes touch them exactly; all arithmetic is exact.
  std::vector<Vec3> lattice;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) lattice.emplace_back(x, y, z);
  for (double cell : {1.0, 2.0, 0.5}) {
    HashGrid grid;
    grid.build(lattice, {}, cell);
    for (const Vec3& c : lattice)
      for (double r : {0.0, 1.0, 2.0}) expect_box_query_exact(grid, lattice, c, r);
    std::vector<double> radii(lattice.size());
    for (size_t i = 0; i < radii.size(); ++i) radii[i] = static_cast<double>(i % 3);
    grid.build(lattice, radii, cell);
    for (const Vec3& p : lattice) expect_point_query_exact(grid, lattice, radii, p);
  }
}

TEST(HashGrid, QueriesOutsideBounds) {
  const std::vector<Vec3> points = random_points(2000, 20, Vec3(0.0), Vec3(1.0));
  const std::vector<double> radii = random_radii(2000, 21, 0.0, 0.05);
  const double nan = std::nan("");
  const std::vector<Vec3> far = {Vec3(5.0, 0.5, 0.5), Vec3(-5.0, -5.0, -5.0), Vec3(1e300),
                                 Vec3(-1e300, 0.5, 1e300), Vec3(kInf, 0.5, 0.5),
                                 Vec3(-kInf, -kInf, kInf), Vec3(nan, 0.5, 0.5), Vec3(nan)};
  HashGrid grid;
  grid.build(points, radii, 0.05);
  for (const Vec3& p : far) {
    size_t visits = 0;
    grid.for_each_candidate_at(p, [&](uint32_t) { ++visits; });
    EXPECT_EQ(visits, 0u);
  }
  grid.build(points, {}, 0.05);
  for (const Vec3& c : far)
    if (is_finite(c)) expect_box_query_exact(grid, points, c, 1.0);
  size_t visits = 0;
  grid.for_each_candidate_in_box(Vec3(nan), Vec3(nan), [&](uint32_t) { ++visits; });
  grid.for_each_candidate_in_box(Vec3(kInf), Vec3(-kInf), [&](uint32_t) { ++visits; });
  grid.for_each_candidate_in_box(Vec3(2.0), Vec3(3.0), [&](uint32_t) { ++visits; });
  EXPECT_EQ(visits, 0u);
  EXPECT_EQ(count_candidates_in_box(grid, Vec3(-kInf), Vec3(kInf)), points.size());
  expect_box_query_exact(grid, points, Vec3(0.5), 1e300);
}

TEST(HashGrid, HugeExtentEnlargesCells) {
  // 2e9 wide with 1e-6 cells would need 2e15 cells per axis: the 21-bit key
  // fields force the cell size up, and queries stay exact.
  std::vector<Vec3> points = random_points(3000, 25, Vec3(-1e9), Vec3(1e9));
  const std::vector<Vec3> cluster = random_points(1000, 26, Vec3(0.0), Vec3(1.0));
  points.insert(points.end(), cluster.begin(), cluster.end());
  HashGrid grid;
  grid.build(points, {}, 1e-6);
  EXPECT_GT(grid.cell_size(), 1.9e9 / double(1 << 21));
  for (size_t q = 0; q < 50; ++q) {
    expect_box_query_exact(grid, points, cluster[q], 0.1);
    expect_box_query_exact(grid, points, points[q], 3e8);
  }
}

TEST(HashGrid, NonFiniteOrInvalidInputIsRejected) {
  std::vector<Vec3> points = random_points(50, 22, Vec3(0.0), Vec3(1.0));
  HashGrid grid;
  grid.build(points, {}, 0.1);
  points[37].y = std::nan("");
  try {
    grid.build(points, {}, 0.1);
    FAIL() << "NaN center accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("37"), std::string::npos) << e.what();
  }
  EXPECT_EQ(grid.item_count(), 50u);  // previous contents kept
  points[37].y = 0.5;
  points[12].z = -kInf;
  EXPECT_THROW(grid.build(points, {}, 0.1), std::invalid_argument);
  points[12].z = 0.5;
  std::vector<double> radii(50, 0.1);
  radii[3] = -0.1;
  EXPECT_THROW(grid.build(points, radii, 0.1), std::invalid_argument);
  radii[3] = std::nan("");
  EXPECT_THROW(grid.build(points, radii, 0.1), std::invalid_argument);
  EXPECT_THROW(grid.build(points, std::vector<double>(49, 0.1), 0.1), std::invalid_argument);
  for (double bad : {0.0, -1.0, kInf, std::nan("")})
    EXPECT_THROW(grid.build(points, {}, bad), std::invalid_argument);
  const std::vector<Vec3> overflow = {Vec3(-1.5e308), Vec3(1.5e308)};  // extent is inf
  EXPECT_THROW(grid.build(overflow, {}, 1.0), std::invalid_argument);
}

TEST(HashGrid, LargeDegenerateInputBuildsBounded) {
  const size_t n = 200000;
  std::vector<Vec3> points = random_points(n, 23, Vec3(0.0), Vec3(1.0));
  for (size_t i = 0; i < n; ++i)
    points[i] = i % 2 ? Vec3(0.25) : Vec3(0.5, std::round(points[i].y * 1e3) / 1e3,
                                          std::round(points[i].z * 1e3) / 1e3);
  HashGrid grid;
  grid.build(points, {}, 0.01);
  EXPECT_EQ(grid.reference_count(), n);
  EXPECT_LE(grid.cell_count(), 4 * n);
  for (const Vec3& c : random_points(60, 24, Vec3(0.2), Vec3(0.6))) expect_box_query_exact(grid, points, c, 0.02);
  expect_box_query_exact(grid, points, Vec3(0.25), 0.0);
}

}  // namespace
}  // namespace ppm
