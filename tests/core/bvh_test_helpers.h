// Shared by the BVH tests: a triangle soup with its BVH, and its nearest hit
// found through the BVH and by brute force over the same triangle test.
#pragma once

#include "geometry/bvh.h"
#include "geometry/bvh_build.h"
#include "geometry/triangle.h"
#include "math/aabb.h"
#include "math/float_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

namespace ppm {

inline std::vector<Aabb> triangle_boxes(const std::vector<TrianglePrim>& tris) {
  std::vector<Aabb> boxes;
  boxes.reserve(tris.size());
  for (const auto& t : tris) boxes.push_back(triangle_box(t));
  return boxes;
}

// `box` contains `exact` and lies within it rounded outwards to float: the build keeps boxes in
// float (bvh_build.cpp), a refit in double.
inline void expect_contains_within_float_rounding(const Aabb& box, const Aabb& exact) {
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(box.lo[a], exact.lo[a]);
    EXPECT_GE(box.lo[a], double(float_down(exact.lo[a])));
    EXPECT_GE(box.hi[a], exact.hi[a]);
    EXPECT_LE(box.hi[a], double(float_up(exact.hi[a])));
  }
}

// A binary tree is depth-first (left child next), every box is the union of its children's (leaves:
// of their primitives' `boxes`, within float rounding), and every primitive is in exactly one leaf.
// Returns its depth.
inline int expect_valid_binary_tree(const BinaryBvh& tree, const std::vector<Aabb>& boxes) {
  std::vector<int> seen(boxes.size(), 0);
  int depth = 0;
  // Returns the subtree's end (the index after its last node) and checks it on the way.
  std::function<uint32_t(uint32_t, int)> check = [&](uint32_t i, int level) -> uint32_t {
    depth = std::max(depth, level);
    const BinaryBvhNode& n = tree.nodes[i];
    Aabb expected;
    if (n.is_leaf()) {
      for (uint32_t k = n.first; k < n.first + n.count; ++k) {
        ++seen[tree.order[k]];
        expected.grow(boxes[tree.order[k]]);
      }
      expect_contains_within_float_rounding(n.box.to_double(), expected);
      return i + 1;
    }
    const uint32_t left_end = check(i + 1, level + 1);
    EXPECT_EQ(left_end, n.first) << "the right child follows the left subtree";
    const uint32_t end = check(n.first, level + 1);
    expected.grow(tree.nodes[i + 1].box.to_double());
    expected.grow(tree.nodes[n.first].box.to_double());
    expect_contains_within_float_rounding(n.box.to_double(), expected);
    return end;
  };
  EXPECT_EQ(check(0, 0), tree.nodes.size());
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; }));
  return depth;
}

struct TriangleSoup {
  std::vector<TrianglePrim> tris;
  Bvh bvh;

  void build() { bvh.build(triangle_boxes(tris)); }
  // Nearest (t, triangle index), (kInf, -1) for a miss.
  std::pair<double, int> bvh_hit(const Ray& r) const {
    double tmax = kInf;
    int best = -1;
    bvh.closest(r.origin, r.direction, tmax, [&](uint32_t slot, double& tm) {
      const uint32_t p = bvh.prim_order()[slot];
      double t, b1, b2;
      if (!intersect_triangle(tris[p], r, tm, t, b1, b2)) return false;
      tm = t;
      best = static_cast<int>(p);
      return true;
    });
    return {best >= 0 ? tmax : kInf, best};
  }
  // bvh_hit for each ray, through the interleaved walks; checks that each
  // ray is reported done exactly once.
  std::vector<std::pair<double, int>> many_hits(const std::vector<Ray>& rays) const {
    std::vector<std::pair<double, int>> out(rays.size(), {kInf, -1});
    std::vector<int> done(rays.size(), 0);
    bvh.closest_many(
        rays.size(), [&](size_t i) -> const Ray& { return rays[i]; },
        [&](size_t i, uint32_t slot, double& tm) {
          const uint32_t p = bvh.prim_order()[slot];
          double t, b1, b2;
          if (!intersect_triangle(tris[p], rays[i], tm, t, b1, b2)) return false;
          tm = t;
          out[i] = {t, static_cast<int>(p)};
          return true;
        },
        NoPrefetch{}, [&](size_t i) { ++done[i]; });
    for (size_t i = 0; i < rays.size(); ++i)
      if (done[i] != 1) out[i] = {-1.0, -2};  // never a real result
    return out;
  }
  std::pair<double, int> brute_hit(const Ray& r) const {
    double tmax = kInf;
    int best = -1;
    for (size_t i = 0; i < tris.size(); ++i) {
      double t, b1, b2;
      if (intersect_triangle(tris[i], r, tmax, t, b1, b2)) {
        tmax = t;
        best = static_cast<int>(i);
      }
    }
    return {tmax, best};
  }
  double bvh_t(const Ray& r) const { return bvh_hit(r).first; }
  double brute_t(const Ray& r) const { return brute_hit(r).first; }
  bool bvh_any(const Ray& r, double limit) const {
    return bvh.any(r.origin, r.direction, limit, [&](uint32_t slot, double& tm) {
      double t, b1, b2;
      return intersect_triangle(tris[bvh.prim_order()[slot]], r, tm, t, b1, b2);
    });
  }
};

}  // namespace ppm
