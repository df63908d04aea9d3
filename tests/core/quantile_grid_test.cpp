// Tests of the quantile grid against brute force: random points and spheres,
// planar and duplicate-heavy sets, values exactly on splits, out-of-bounds and
// non-finite input. Every query compares the exact set "items within r" found
// through the index with the brute-force set, and checks that point items (and
// point queries over spheres) are visited at most once.
#include "ppm/quantile_grid.h"

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

void expect_strictly_increasing_splits(const QuantileGrid& grid) {
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& s = grid.splits(a);
    EXPECT_EQ(s.size() + 1, grid.slab_count(a));
    for (size_t k = 1; k < s.size(); ++k) ASSERT_LT(s[k - 1], s[k]) << "axis " << a;
  }
}

TEST(QuantileGrid, SlabIndexMatchesUpperBound) {
  std::vector<Vec3> points = random_points(20000, 1, Vec3(-1.0), Vec3(1.0));
  for (Vec3& p : points) p = glm::round(p * 50.0) / 50.0;  // many repeated coordinates
  QuantileGrid grid(1.0);
  grid.build(points, {});
  expect_strictly_increasing_splits(grid);
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& s = grid.splits(a);
    ASSERT_GT(s.size(), 10u);
    std::vector<double> probes = {-kInf, kInf, -5.0, 5.0, 0.0};
    for (double v : s) {
      probes.push_back(v);
      probes.push_back(std::nextafter(v, -kInf));
      probes.push_back(std::nextafter(v, kInf));
    }
    for (double x : probes) {
      const auto expected = std::upper_bound(s.begin(), s.end(), x) - s.begin();
      EXPECT_EQ(grid.slab_index(a, x), static_cast<uint32_t>(expected)) << "x = " << x;
    }
    EXPECT_EQ(grid.slab_index(a, std::nan("")), 0u);
  }
}

// Splits crowded into a tiny part of their range (coordinates spread over 12
// orders of magnitude) put many splits in one lookup bucket and leave most
// buckets empty; the lookup must still give exactly upper_bound's answer.
TEST(QuantileGrid, SlabIndexExactWithCrowdedSplits) {
  std::vector<Vec3> points = random_points(20000, 7, Vec3(0.0), Vec3(1.0));
  for (Vec3& p : points) p = Vec3(std::pow(10.0, 12.0 * p.x - 6.0), -std::pow(10.0, 8.0 * p.y), p.z * 1e-300);
  QuantileGrid grid(1.0);
  grid.build(points, {});
  for (int a = 0; a < 3; ++a) {
    const std::vector<double>& s = grid.splits(a);
    std::vector<double> probes = {-kInf, kInf, 0.0, -0.0, 1e300, -1e300};
    for (double v : s) {
      probes.push_back(v);
      probes.push_back(std::nextafter(v, -kInf));
      probes.push_back(std::nextafter(v, kInf));
    }
    for (const Vec3& p : points) probes.push_back(p[a]);
    for (double x : probes) {
      const auto expected = std::upper_bound(s.begin(), s.end(), x) - s.begin();
      ASSERT_EQ(grid.slab_index(a, x), static_cast<uint32_t>(expected)) << "axis " << a << ", x = " << x;
    }
    EXPECT_EQ(grid.slab_index(a, std::nan("")), 0u);
  }
}

TEST(QuantileGrid, RandomPointsBoxQueriesMatchBruteForce) {
  const std::vector<Vec3> points = random_points(4000, 2, Vec3(0.0), Vec3(1.0));
  const std::vector<Vec3> queries = random_points(300, 3, Vec3(-0.1), Vec3(1.1));
  const std::vector<double> radii = random_radii(300, 4, 0.005, 0.3);
  for (double target : {0.5, 1.0, 4.0, 16.0}) {
    QuantileGrid grid(target);
    grid.build(points, {});
    EXPECT_EQ(grid.item_count(), points.size());
    EXPECT_EQ(grid.reference_count(), points.size());
    expect_strictly_increasing_splits(grid);
    for (size_t q = 0; q < queries.size(); ++q) expect_box_query_exact(grid, points, queries[q], radii[q]);
  }
}

// The point fill is split over threads by ranges of cells; the stored order
// must be the one-thread order, so that images do not depend on the thread
// count. Enough points for several parts, on walls and in the volume.
TEST(QuantileGrid, PointBuildDoesNotDependOnThreads) {
  std::vector<Vec3> points = three_walls(60000, 21);
  const std::vector<Vec3> volume = random_points(40000, 22, Vec3(-1.0), Vec3(2.0));
  points.insert(points.end(), volume.begin(), volume.end());
  const std::vector<Vec3> queries = random_points(200, 23, Vec3(-0.5), Vec3(1.5));
  auto visits = [&](int threads) {
    QuantileGrid grid;
    grid.build(points, {}, threads);
    std::vector<uint32_t> order;
    grid.for_each_candidate_in_box(Vec3(-10.0), Vec3(10.0), [&](uint32_t i) { order.push_back(i); });
    for (const Vec3& q : queries)
      grid.for_each_candidate_in_box(q - 0.05, q + 0.05, [&](uint32_t i) { order.push_back(i); });
    return order;
  };
  const std::vector<uint32_t> one = visits(1);
  ASSERT_GE(one.size(), points.size());
  for (int threads : {2, 3, 7}) EXPECT_EQ(visits(threads), one) << threads << " threads";
  QuantileGrid grid;
  grid.build(points, {}, 3);
  for (size_t q = 0; q < 50; ++q) expect_box_query_exact(grid, points, queries[q], 0.02 + 0.002 * q);
}

TEST(QuantileGrid, RelabelledRunsMatchBruteForce) {
  std::vector<Vec3> points = three_walls(30000, 24);
  const std::vector<Vec3> volume = random_points(5000, 25, Vec3(0.0), Vec3(1.0));
  points.insert(points.end(), volume.begin(), volume.end());
  const std::vector<Vec3> queries = random_points(150, 26, Vec3(-0.1), Vec3(1.1));
  const std::vector<double> radii = random_radii(150, 27, 0.001, 0.2);
  QuantileGrid grid;
  expect_run_queries_exact(grid, [](QuantileGrid& g, const std::vector<Vec3>& p) { g.build(p, {}, 2); }, points,
                           queries, radii);
}

TEST(QuantileGrid, RandomSpheresPointQueriesMatchBruteForce) {
  const std::vector<Vec3> centers = random_points(3000, 5, Vec3(0.0), Vec3(1.0));
  const std::vector<double> radii = random_radii(3000, 6, 0.0, 0.12);
  std::vector<Vec3> queries = random_points(3000, 7, Vec3(-0.1), Vec3(1.1));
  for (size_t i = 0; i < 300; ++i) {
    queries.push_back(centers[i]);                               // radius-0 spheres included
    queries.push_back(centers[i] + Vec3(radii[i], 0.0, 0.0));    // on the sphere
    queries.push_back(centers[i] - Vec3(0.0, 0.0, radii[i]));
  }
  for (double target : {1.0, 4.0}) {
    QuantileGrid grid(target);
    grid.build(centers, radii);
    EXPECT_GE(grid.reference_count(), centers.size());
    for (const Vec3& p : queries) expect_point_query_exact(grid, centers, radii, p);
    for (size_t q = 0; q < 200; ++q)
      expect_sphere_box_superset(grid, centers, radii, queries[q] - 0.05, queries[q] + 0.05);
  }
}

TEST(QuantileGrid, PlanarPointsAllXEqual) {
  const size_t n = 100000;
  std::vector<Vec3> points = random_points(n, 8, Vec3(0.0), Vec3(1.0));
  for (Vec3& p : points) p.x = 1.0;
  const double target = 4.0;
  QuantileGrid grid(target);
  grid.build(points, {});
  expect_strictly_increasing_splits(grid);
  EXPECT_EQ(grid.slab_count(0), 1u);
  EXPECT_EQ(grid.reference_count(), n);
  EXPECT_LE(grid.cell_count(), static_cast<size_t>(1.1 * n / target) + 1);
  // The budget the x axis cannot use goes to y and z: cells stay small.
  EXPECT_LE(static_cast<double>(n) / grid.nonempty_cell_count(), 2.0 * target);
  const std::vector<Vec3> centers = random_points(150, 9, Vec3(0.5, 0.0, 0.0), Vec3(1.5, 1.0, 1.0));
  for (size_t q = 0; q < centers.size(); ++q) {
    expect_box_query_exact(grid, points, centers[q], 0.02 + 0.3 * (q % 7) / 7.0);
    // Boxes whose hi or lo face is exactly the plane, with a point exactly at distance r.
    const Vec3& p = points[q * 97];
    expect_box_query_exact(grid, points, Vec3(0.75, p.y, p.z), 0.25);
    expect_box_query_exact(grid, points, Vec3(1.25, p.y, p.z), 0.25);
  }
}

TEST(QuantileGrid, PlanarSpheresAllXEqual) {
  const size_t n = 50000;
  std::vector<Vec3> centers = random_points(n, 10, Vec3(0.0), Vec3(1.0));
  for (Vec3& c : centers) c.x = 1.0;
  const std::vector<double> radii = random_radii(n, 11, 0.002, 0.01);
  QuantileGrid grid(0.25);
  grid.build(centers, radii);
  EXPECT_EQ(grid.slab_count(0), 1u);
  // The count target alone would cut ~450 slabs per axis (0.002 wide) and list
  // each sphere (up to 0.02 across) in ~44 cells; slabs are kept at least a
  // mean radius (0.006) wide instead: about 9.5 references per sphere.
  EXPECT_LE(grid.reference_count(), 12 * n);
  std::vector<Vec3> queries = random_points(2000, 12, Vec3(1.0, 0.0, 0.0), Vec3(1.0, 1.0, 1.0));
  for (size_t i = 0; i < 500; ++i) queries.push_back(centers[i] + Vec3(radii[i], 0.0, 0.0));
  for (const Vec3& p : queries) expect_point_query_exact(grid, centers, radii, p);
}

TEST(QuantileGrid, PointsOnALineGetAllTheSlabs) {
  // y and z are constant: the whole cell budget goes to x.
  const size_t n = 20000;
  std::vector<Vec3> points = random_points(n, 28, Vec3(0.0), Vec3(1.0));
  for (Vec3& p : points) p.y = p.z = 0.5;
  QuantileGrid grid(2.0);
  grid.build(points, {});
  EXPECT_EQ(grid.slab_count(1), 1u);
  EXPECT_EQ(grid.slab_count(2), 1u);
  EXPECT_GE(grid.slab_count(0), n / 4);
  EXPECT_LE(grid.cell_count(), static_cast<size_t>(1.1 * n / 2.0) + 1);
  for (size_t q = 0; q < 200; ++q) expect_box_query_exact(grid, points, points[q * 13], 0.001 * (q % 4));
  const std::vector<double> radii = random_radii(n, 29, 0.0, 0.002);
  grid.build(points, radii);
  for (size_t q = 0; q < 500; ++q) expect_point_query_exact(grid, points, radii, points[q * 7] + Vec3(0.0, 0.001, 0.0));
}

TEST(QuantileGrid, ThreeWallsOfABox) {
  const size_t n = 30000;
  const std::vector<Vec3> points = three_walls(n, 13);
  QuantileGrid grid(4.0);
  grid.build(points, {});
  expect_strictly_increasing_splits(grid);
  EXPECT_EQ(grid.reference_count(), n);
  EXPECT_LE(grid.cell_count(), static_cast<size_t>(1.1 * n / 4.0) + 1);
  const std::vector<Vec3> queries = three_walls(300, 14);
  for (size_t q = 0; q < queries.size(); ++q)
    expect_box_query_exact(grid, points, queries[q], 0.01 + 0.1 * (q % 5) / 5.0);

  const std::vector<double> radii = random_radii(n, 15, 0.002, 0.03);
  grid.build(points, radii);
  EXPECT_LE(grid.reference_count(), 8 * n);
  const std::vector<Vec3> photons = three_walls(3000, 16);
  for (const Vec3& p : photons) expect_point_query_exact(grid, points, radii, p);
  for (size_t i = 0; i < 300; ++i) expect_point_query_exact(grid, points, radii, points[i]);
}

TEST(QuantileGrid, WallsSitInsideSlabs) {
  // Walls x = 0 and x = 1 plus a filled interior: many quantiles land on the
  // wall values, yet neither may become a split, or every small sphere on the
  // wall would straddle two slabs.
  const size_t n = 30000;
  std::vector<Vec3> points = random_points(n, 27, Vec3(0.0), Vec3(1.0));
  for (size_t i = 0; i < n; ++i)
    if (i % 5 < 2) points[i].x = double(i % 5);  // 40% on the walls x = 0 and x = 1
  QuantileGrid grid(2.0);
  grid.build(points, {});
  expect_strictly_increasing_splits(grid);
  for (double s : grid.splits(0)) {
    EXPECT_GT(s, 0.0);
    EXPECT_LT(s, 1.0 - 1e-3);
  }
  std::vector<double> radii(n, 1e-4);
  grid.build(points, radii);
  const uint32_t wall_slab = grid.slab_index(0, 1.0);
  for (size_t i = 1; i < n; i += 5) {
    EXPECT_EQ(grid.slab_index(0, points[i].x - 1e-4), wall_slab);
    EXPECT_EQ(grid.slab_index(0, points[i].x + 1e-4), wall_slab);
  }
  for (size_t i = 0; i < 2000; ++i) expect_point_query_exact(grid, points, radii, points[i]);
}

TEST(QuantileGrid, HeavyDuplicates) {
  const Vec3 p(0.3, 0.6, 0.9);
  const std::vector<Vec3> copies(1000, p);
  QuantileGrid grid(1.0);
  grid.build(copies, {});
  EXPECT_EQ(grid.cell_count(), 1u);
  EXPECT_EQ(grid.reference_count(), 1000u);
  expect_box_query_exact(grid, copies, p, 0.0);
  expect_box_query_exact(grid, copies, p + Vec3(0.1, 0.0, 0.0), 0.1);
  expect_box_query_exact(grid, copies, p + Vec3(0.2, 0.0, 0.0), 0.1);

  const std::vector<double> radii(1000, 0.1);
  grid.build(copies, radii);
  expect_point_query_exact(grid, copies, radii, p);
  expect_point_query_exact(grid, copies, radii, p + Vec3(0.0, 0.1, 0.0));
  expect_point_query_exact(grid, copies, radii, p + Vec3(0.0, 0.2, 0.0));

  // Duplicates mixed with spread points.
  std::vector<Vec3> mixed = random_points(1000, 17, Vec3(0.0), Vec3(1.0));
  mixed.insert(mixed.end(), copies.begin(), copies.end());
  grid.build(mixed, {});
  expect_strictly_increasing_splits(grid);
  EXPECT_EQ(grid.reference_count(), mixed.size());
  for (const Vec3& c : random_points(100, 18, Vec3(0.0), Vec3(1.0))) expect_box_query_exact(grid, mixed, c, 0.15);
  expect_box_query_exact(grid, mixed, p, 0.05);
}

TEST(QuantileGrid, SinglePoint) {
  const std::vector<Vec3> one = {Vec3(2.0, -1.0, 0.5)};
  QuantileGrid grid;
  grid.build(one, {});
  EXPECT_EQ(grid.cell_count(), 1u);
  expect_box_query_exact(grid, one, one[0], 0.0);
  expect_box_query_exact(grid, one, one[0] + Vec3(1.0), 1.0);
  expect_box_query_exact(grid, one, one[0] + Vec3(1.0), 2.0);
  const std::vector<double> radius = {0.5};
  grid.build(one, radius);
  expect_point_query_exact(grid, one, radius, one[0]);
  expect_point_query_exact(grid, one, radius, one[0] + Vec3(0.0, 0.5, 0.0));
  expect_point_query_exact(grid, one, radius, one[0] + Vec3(0.0, 0.6, 0.0));
}

TEST(QuantileGrid, EmptyInput) {
  QuantileGrid grid;
  const auto check_empty = [&] {
    EXPECT_EQ(grid.item_count(), 0u);
    EXPECT_EQ(grid.reference_count(), 0u);
    size_t visits = 0;
    grid.for_each_candidate_at(Vec3(0.0), [&](uint32_t) { ++visits; });
    grid.for_each_candidate_in_box(Vec3(-1e300), Vec3(1e300), [&](uint32_t) { ++visits; });
    EXPECT_EQ(visits, 0u);
  };
  check_empty();  // never built
  grid.build({}, {});
  check_empty();
  grid.build(random_points(100, 19, Vec3(0.0), Vec3(1.0)), {});
  grid.build({}, {});
  check_empty();
}

TEST(QuantileGrid, ValuesExactlyOnSplits) {
  // Integer lattice 0..7 (every coordinate value repeats 64 times): splits land
  // on integers and integer boxes touch them exactly; all arithmetic is exact.
  std::vector<Vec3> lattice;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) lattice.emplace_back(x, y, z);
  QuantileGrid grid(1.0);
  grid.build(lattice, {});
  expect_strictly_increasing_splits(grid);
  for (int a = 0; a < 3; ++a) {
    ASSERT_GE(grid.splits(a).size(), 3u);
    for (double s : grid.splits(a)) EXPECT_EQ(s, std::round(s));
  }
  for (const Vec3& c : lattice)
    for (double r : {0.0, 1.0, 2.0}) expect_box_query_exact(grid, lattice, c, r);
  // Boxes with one face exactly on a split and a point exactly on that face.
  for (int a = 0; a < 3; ++a)
    for (double s : grid.splits(a)) {
      Vec3 c(3.0);
      c[a] = s - 1.0;
      expect_box_query_exact(grid, lattice, c, 1.0);  // hi face on the split
      c[a] = s + 1.0;
      expect_box_query_exact(grid, lattice, c, 1.0);  // lo face on the split
    }
  std::vector<double> radii(lattice.size());
  for (size_t i = 0; i < radii.size(); ++i) radii[i] = static_cast<double>(i % 3);
  grid.build(lattice, radii);
  for (const Vec3& p : lattice) expect_point_query_exact(grid, lattice, radii, p);
}

TEST(QuantileGrid, QueriesOutsideBounds) {
  const std::vector<Vec3> points = random_points(2000, 20, Vec3(0.0), Vec3(1.0));
  const std::vector<double> radii = random_radii(2000, 21, 0.0, 0.05);
  const double nan = std::nan("");
  const std::vector<Vec3> far = {Vec3(5.0, 0.5, 0.5), Vec3(-5.0, -5.0, -5.0), Vec3(1e300),
                                 Vec3(-1e300, 0.5, 1e300), Vec3(kInf, 0.5, 0.5),
                                 Vec3(-kInf, -kInf, kInf), Vec3(nan, 0.5, 0.5), Vec3(nan)};
  QuantileGrid grid;
  grid.build(points, radii);
  for (const Vec3& p : far) expect_point_query_exact(grid, points, radii, p);
  grid.build(points, {});
  for (const Vec3& c : far)
    if (is_finite(c)) expect_box_query_exact(grid, points, c, 1.0);
  size_t visits = 0;
  grid.for_each_candidate_in_box(Vec3(nan), Vec3(nan), [&](uint32_t) { ++visits; });
  grid.for_each_candidate_in_box(Vec3(kInf), Vec3(-kInf), [&](uint32_t) { ++visits; });
  EXPECT_LT(visits, points.size());
  // A box around everything visits every point exactly once.
  EXPECT_EQ(count_candidates_in_box(grid, Vec3(-kInf), Vec3(kInf)), points.size());
  expect_box_query_exact(grid, points, Vec3(0.5), 1e300);
}

TEST(QuantileGrid, NonFiniteOrInvalidInputIsRejected) {
  std::vector<Vec3> points = random_points(50, 22, Vec3(0.0), Vec3(1.0));
  QuantileGrid grid;
  grid.build(points, {});
  points[37].y = std::nan("");
  try {
    grid.build(points, {});
    FAIL() << "NaN center accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("37"), std::string::npos) << e.what();
  }
  EXPECT_EQ(grid.item_count(), 50u);  // previous contents kept
  points[37].y = 0.5;
  points[12].z = -kInf;
  EXPECT_THROW(grid.build(points, {}), std::invalid_argument);
  points[12].z = 0.5;
  std::vector<double> radii(50, 0.1);
  radii[3] = -0.1;
  EXPECT_THROW(grid.build(points, radii), std::invalid_argument);
  radii[3] = std::nan("");
  EXPECT_THROW(grid.build(points, radii), std::invalid_argument);
  radii[3] = kInf;
  EXPECT_THROW(grid.build(points, radii), std::invalid_argument);
  EXPECT_THROW(grid.build(points, std::vector<double>(49, 0.1)), std::invalid_argument);
  EXPECT_THROW(QuantileGrid(0.0), std::invalid_argument);
  EXPECT_THROW(QuantileGrid(std::nan("")), std::invalid_argument);
}

TEST(QuantileGrid, LargeDegenerateInputBuildsBounded) {
  // Half exact duplicates, half on the plane x = 0.5 with coordinates on a
  // 1e-3 lattice: a quadratic or split-repeating build would show here.
  const size_t n = 200000;
  std::vector<Vec3> points = random_points(n, 23, Vec3(0.0), Vec3(1.0));
  for (size_t i = 0; i < n; ++i)
    points[i] = i % 2 ? Vec3(0.25) : Vec3(0.5, std::round(points[i].y * 1e3) / 1e3,
                                          std::round(points[i].z * 1e3) / 1e3);
  const double target = 2.0;
  QuantileGrid grid(target);
  grid.build(points, {});
  expect_strictly_increasing_splits(grid);
  EXPECT_EQ(grid.reference_count(), n);
  EXPECT_LE(grid.cell_count(), static_cast<size_t>(1.1 * n / target) + 1);
  for (const Vec3& c : random_points(60, 24, Vec3(0.2), Vec3(0.6))) expect_box_query_exact(grid, points, c, 0.02);
  expect_box_query_exact(grid, points, Vec3(0.25), 0.0);
}

}  // namespace
}  // namespace ppm
