// Shared helpers of the spatial index tests (quantile grid, hashed grid):
// random and planar point sets, and query checks against brute force that
// work for either index (they share one query interface).
#pragma once

#include "math/rng.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace ppm {
namespace grid_test {

inline std::vector<Vec3> random_points(size_t n, uint64_t seed, const Vec3& lo, const Vec3& hi) {
  std::vector<Vec3> points(n);
  for (size_t i = 0; i < n; ++i) {
    Rng rng(seed, 1, i);
    const double x = rng.uniform(), y = rng.uniform(), z = rng.uniform();
    points[i] = lo + Vec3(x, y, z) * (hi - lo);
  }
  return points;
}

inline std::vector<double> random_radii(size_t n, uint64_t seed, double rmin, double rmax) {
  std::vector<double> radii(n);
  for (size_t i = 0; i < n; ++i) radii[i] = rmin + (rmax - rmin) * Rng(seed, 2, i).uniform();
  return radii;
}

// Points on the walls x = 0, y = 0 and z = 0 of the unit box, n / 3 each.
inline std::vector<Vec3> three_walls(size_t n, uint64_t seed) {
  std::vector<Vec3> points = random_points(n, seed, Vec3(0.0), Vec3(1.0));
  for (size_t i = 0; i < n; ++i) points[i][i % 3] = 0.0;
  return points;
}

inline bool within(const Vec3& p, const Vec3& c, double r) {
  const Vec3 d = p - c;
  return glm::dot(d, d) <= r * r;
}

// Mode A: the spheres containing p, through the index and by brute force.
template <class Grid>
void expect_point_query_exact(const Grid& grid, const std::vector<Vec3>& centers,
                              const std::vector<double>& radii, const Vec3& p) {
  std::vector<uint32_t> candidates, found, expected;
  grid.for_each_candidate_at(p, [&](uint32_t i) { candidates.push_back(i); });
  std::sort(candidates.begin(), candidates.end());
  ASSERT_TRUE(std::adjacent_find(candidates.begin(), candidates.end()) == candidates.end())
      << "item visited twice at p = " << p.x << " " << p.y << " " << p.z;
  for (uint32_t i : candidates) {
    ASSERT_LT(i, centers.size());
    if (within(p, centers[i], radii[i])) found.push_back(i);
  }
  for (uint32_t i = 0; i < centers.size(); ++i)
    if (within(p, centers[i], radii[i])) expected.push_back(i);
  EXPECT_EQ(found, expected) << "p = " << p.x << " " << p.y << " " << p.z;
}

// Mode B: the points within r of c, through a box query and by brute force.
template <class Grid>
void expect_box_query_exact(const Grid& grid, const std::vector<Vec3>& points,
                            const Vec3& c, double r) {
  std::vector<uint32_t> candidates, found, expected;
  grid.for_each_candidate_in_box(c - r, c + r, [&](uint32_t i) { candidates.push_back(i); });
  std::sort(candidates.begin(), candidates.end());
  ASSERT_TRUE(std::adjacent_find(candidates.begin(), candidates.end()) == candidates.end())
      << "point visited twice for c = " << c.x << " " << c.y << " " << c.z << " r = " << r;
  for (uint32_t i : candidates) {
    ASSERT_LT(i, points.size());
    if (within(points[i], c, r)) found.push_back(i);
  }
  for (uint32_t i = 0; i < points.size(); ++i)
    if (within(points[i], c, r)) expected.push_back(i);
  EXPECT_EQ(found, expected) << "c = " << c.x << " " << c.y << " " << c.z << " r = " << r;
}

// Mode B after relabel_in_cell_order: builds over `points`, relabels, and
// checks that the runs of for_each_run_in_box, mapped back to the original
// labels, are exactly the brute-force points within r of each query.
template <class Grid, class Build>
void expect_run_queries_exact(Grid& grid, Build&& build, const std::vector<Vec3>& points,
                              const std::vector<Vec3>& queries, const std::vector<double>& radii) {
  build(grid, points);
  std::vector<uint32_t> old_of_new;
  grid.relabel_in_cell_order(old_of_new);
  ASSERT_EQ(old_of_new.size(), points.size());
  std::vector<uint32_t> sorted(old_of_new);
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "old_of_new is not a permutation";
  for (size_t q = 0; q < queries.size(); ++q) {
    const Vec3 c = queries[q];
    const double r = radii[q];
    std::vector<uint32_t> found, expected;
    grid.for_each_run_in_box(c - r, c + r, [&](uint32_t begin, uint32_t end) {
      ASSERT_LE(begin, end);
      ASSERT_LE(end, points.size());
      for (uint32_t k = begin; k < end; ++k)
        if (within(points[old_of_new[k]], c, r)) found.push_back(old_of_new[k]);
    });
    std::sort(found.begin(), found.end());
    ASSERT_TRUE(std::adjacent_find(found.begin(), found.end()) == found.end()) << "point visited twice";
    for (uint32_t i = 0; i < points.size(); ++i)
      if (within(points[i], c, r)) expected.push_back(i);
    EXPECT_EQ(found, expected) << "c = " << c.x << " " << c.y << " " << c.z << " r = " << r;
  }
}

// Mode A box query: every sphere meeting the box must be a candidate.
template <class Grid>
void expect_sphere_box_superset(const Grid& grid, const std::vector<Vec3>& centers,
                                const std::vector<double>& radii, const Vec3& lo, const Vec3& hi) {
  std::vector<char> seen(centers.size(), 0);
  grid.for_each_candidate_in_box(lo, hi, [&](uint32_t i) {
    ASSERT_LT(i, centers.size());
    seen[i] = 1;
  });
  for (size_t i = 0; i < centers.size(); ++i) {
    const Vec3 d = glm::clamp(centers[i], lo, hi) - centers[i];
    if (glm::dot(d, d) <= radii[i] * radii[i]) {
      EXPECT_TRUE(seen[i]) << "sphere " << i << " missed";
    }
  }
}

template <class Grid>
size_t count_candidates_in_box(const Grid& grid, const Vec3& lo, const Vec3& hi) {
  size_t count = 0;
  grid.for_each_candidate_in_box(lo, hi, [&](uint32_t) { ++count; });
  return count;
}

}  // namespace grid_test
}  // namespace ppm
