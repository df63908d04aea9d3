// The BVH must return exactly the nearest hit that brute force finds, on
// random triangle soups, on degenerate input (coincident centroids, flat
// sheets, zero-area triangles), and for rays along the box faces.
#include "geometry/bvh.h"
#include "geometry/bvh_build.h"
#include "geometry/triangle.h"
#include "math/rng.h"
#include "bvh_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <vector>

namespace ppm {
namespace {

Vec3 random_point(Rng& rng, double scale) {
  return scale * Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
}

Ray random_ray(Rng& rng, double scale) {
  const Vec3 o = random_point(rng, 3.0 * scale);
  const Vec3 target = random_point(rng, scale);
  return Ray{o, glm::normalize(target - o)};
}

void expect_agree(const TriangleSoup& soup, Rng& rng, double scale, int rays) {
  int hits = 0;
  for (int i = 0; i < rays; ++i) {
    const Ray r = random_ray(rng, scale);
    const auto a = soup.bvh_hit(r), b = soup.brute_hit(r);
    ASSERT_EQ(a.first, b.first) << "ray " << i;
    hits += b.second >= 0;
  }
  EXPECT_GT(hits, rays / 20) << "test rays should hit something";
}

TEST(Bvh, MatchesBruteForceOnRandomTriangles) {
  for (double scale : {1e-3, 1.0, 1e4}) {
    Rng rng(1, 2, static_cast<uint64_t>(scale * 1000));
    TriangleSoup soup;
    for (int i = 0; i < 3000; ++i) {
      const Vec3 c = random_point(rng, scale);
      soup.tris.push_back({c, random_point(rng, 0.05 * scale), random_point(rng, 0.05 * scale)});
    }
    soup.build();
    expect_agree(soup, rng, scale, 3000);
  }
}

// Over 2^16 primitives the top subtrees are built on threads of their own and joined: the tree
// must still be depth-first (left child next), every box the union of its children's (leaves: of
// their primitives'), and every primitive in exactly one leaf.
TEST(Bvh, SubtreesBuiltInParallelJoinIntoOneDepthFirstTree) {
  Rng rng(11, 0, 0);
  std::vector<Aabb> boxes(300000);
  for (Aabb& b : boxes) {
    const Vec3 c = random_point(rng, 100.0);
    b = Aabb{};
    b.grow(c);
    b.grow(c + Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
  }
  expect_valid_binary_tree(build_binary_bvh(boxes, 4), boxes);
}

// Over 2^17 binary nodes the collapse emits its subtrees on all threads and places them after the
// top levels: every 4-wide node must be reached exactly once from the root (none left over, none
// shared), every leaf slot named once, and the hits must be brute force's.
TEST(Bvh, SubtreesCollapsedInParallelFormOneTree) {
  Rng rng(12, 0, 0);
  TriangleSoup soup;
  for (int i = 0; i < 200000; ++i) {
    const Vec3 c = random_point(rng, 100.0);
    soup.tris.push_back({c, random_point(rng, 1.0), random_point(rng, 1.0)});
  }
  soup.build();
  const auto& nodes = soup.bvh.nodes();
  std::vector<int> reached(nodes.size(), 0), slots(soup.tris.size(), 0);
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    ASSERT_LT(i, nodes.size());
    if (++reached[i] > 1) continue;  // counted; its children were already walked
    for (int k = 0; k < 4; ++k) {
      if (nodes[i].count[k] > 0) {
        for (uint32_t s = nodes[i].child[k]; s < nodes[i].child[k] + nodes[i].count[k]; ++s) ++slots.at(s);
      } else if (nodes[i].box[0][k] <= nodes[i].box[1][k]) {
        stack.push_back(nodes[i].child[k]);  // an inner child (an unused one has an empty box)
      }
    }
  }
  EXPECT_TRUE(std::all_of(reached.begin(), reached.end(), [](int k) { return k == 1; }));
  EXPECT_TRUE(std::all_of(slots.begin(), slots.end(), [](int k) { return k == 1; }));
  expect_agree(soup, rng, 100.0, 300);
}

TEST(Bvh, CoincidentCentroidsAndFlatSheet) {
  Rng rng(3, 4, 5);
  TriangleSoup soup;
  for (int i = 0; i < 2000; ++i) {  // all centred on the origin, different sizes
    const double s = 0.1 + rng.uniform();
    soup.tris.push_back({Vec3(-s, -s, 0.0) * 0.5, Vec3(s, 0.0, 0.0), Vec3(0.0, s, rng.uniform() * 0.01)});
  }
  for (int i = 0; i < 2000; ++i) {  // a flat sheet: zero extent along z
    const Vec3 c(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, 0.25);
    soup.tris.push_back({c, Vec3(0.02, 0, 0), Vec3(0, 0.02, 0)});
  }
  soup.tris.push_back({Vec3(0.1, 0.1, 0.1), Vec3(0.0), Vec3(0.0)});  // zero-area
  soup.build();
  expect_agree(soup, rng, 2.0, 3000);
  // Depth stays bounded even though SAH cannot split coincident centroids.
  EXPECT_LT(soup.bvh.nodes().size(), 4 * soup.tris.size());
}

TEST(Bvh, AxisAlignedRaysAlongFaces) {
  TriangleSoup soup;
  soup.tris.push_back({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
  soup.tris.push_back({Vec3(2, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
  soup.build();
  // Ray straight down onto the first triangle: direction has two zero components.
  const Ray down{Vec3(0.25, 0.25, 5.0), Vec3(0, 0, -1)};
  EXPECT_DOUBLE_EQ(soup.bvh_hit(down).first, 5.0);
  // Ray lying in the plane z = 0 between the triangles' boxes misses cleanly.
  const Ray along{Vec3(-1, 5, 0), Vec3(1, 0, 0)};
  EXPECT_EQ(soup.bvh_hit(along).second, -1);
}

TEST(Bvh, AnyHitAgreesWithClosest) {
  Rng rng(7, 7, 7);
  TriangleSoup soup;
  for (int i = 0; i < 1000; ++i)
    soup.tris.push_back({random_point(rng, 1.0), random_point(rng, 0.1), random_point(rng, 0.1)});
  soup.build();
  for (int i = 0; i < 2000; ++i) {
    const Ray r = random_ray(rng, 1.0);
    const double t = soup.brute_hit(r).first;
    const double limit = 0.5 + rng.uniform() * 3.0;
    const bool blocked = soup.bvh.any(r.origin, r.direction, limit, [&](uint32_t slot, double& tm) {
      double tt, b1, b2;
      return intersect_triangle(soup.tris[soup.bvh.prim_order()[slot]], r, tm, tt, b1, b2);
    });
    ASSERT_EQ(blocked, t < limit) << "ray " << i;
  }
}

// Interleaved walks (closest_many) give each ray exactly what a walk on its
// own gives, for batches smaller and larger than the number of walks in
// flight, empty and tiny trees, and rays that take the brute-force path.
TEST(Bvh, InterleavedWalksMatchOneAtATime) {
  Rng rng(4, 4, 4);
  for (int triangles : {0, 1, 3, 50, 3000}) {
    TriangleSoup soup;
    for (int i = 0; i < triangles; ++i)
      soup.tris.push_back({random_point(rng, 1.0), random_point(rng, 0.2), random_point(rng, 0.2)});
    soup.build();
    for (int count : {0, 1, Bvh::kInterleavedRays - 1, Bvh::kInterleavedRays + 1, 2000}) {
      std::vector<Ray> rays;
      for (int i = 0; i < count; ++i) {
        Ray r = random_ray(rng, 1.0);
        if (i % 97 == 5) r.origin = Vec3(0.0, 0.0, 1e38);  // beyond the float slab test
        if (i % 97 == 6) r.origin = Vec3(0.0, 0.0, 1e38), r.direction = Vec3(0, 0, -1);
        rays.push_back(r);
      }
      const auto many = soup.many_hits(rays);
      int hits = 0;
      for (int i = 0; i < count; ++i) {
        ASSERT_EQ(many[i], soup.bvh_hit(rays[i])) << triangles << " triangles, " << count << " rays, ray " << i;
        hits += many[i].second >= 0;
      }
      if (triangles >= 3000 && count >= 100) EXPECT_GT(hits, count / 10);
    }
  }
}

TEST(Bvh, RejectsNonFiniteBoxes) {
  Bvh bvh;
  Aabb bad;
  bad.grow(Vec3(0.0));
  bad.grow(Vec3(std::nan(""), 0.0, 0.0));
  bad.hi.x = std::nan("");
  EXPECT_THROW(bvh.build({bad}), std::invalid_argument);
  EXPECT_NO_THROW(bvh.build({}));
}

// The build reads the boxes in blocks on several threads; the message names the first bad box
// whichever thread found which.
TEST(Bvh, NamesTheFirstNonFiniteBoxAmongMany) {
  std::vector<Aabb> boxes(300000, Aabb{Vec3(0.0), Vec3(1.0)});
  boxes[250000].lo.y = std::numeric_limits<double>::infinity();
  boxes[70001].hi.z = std::nan("");
  try {
    build_binary_bvh(boxes, kBinaryLeafSize);
    FAIL() << "a non-finite box was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "BVH: primitive 70001 has a non-finite bounding box");
  }
}

}  // namespace
}  // namespace ppm
