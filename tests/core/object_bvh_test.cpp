// The object-by-object BVH (geometry/object_bvh.h): its joined tree is a valid depth-first tree over
// every primitive, each object's primitives take contiguous slots, a refitted object's tree is as
// valid as a fresh one, a rebuild keeps the subtrees it is told to reuse, and the 4-wide BVH collapsed
// from it finds exactly the hits brute force does.
#include "geometry/object_bvh.h"

#include "geometry/bvh.h"
#include "geometry/triangle.h"
#include "math/rng.h"
#include "bvh_test_helpers.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace ppm {
namespace {

// `objects` clusters of small triangles, cluster k's triangles interleaved with the others' in the
// input (object_of[i] = i % objects), so that the slots must regroup them.
struct Clusters {
  std::vector<TrianglePrim> tris;
  std::vector<uint32_t> object_of;
  uint32_t objects;

  Clusters(Rng& rng, uint32_t objects, int per_object) : objects(objects) {
    std::vector<Vec3> centres;
    for (uint32_t k = 0; k < objects; ++k) centres.push_back(10.0 * unit_cube(rng));
    for (int i = 0; i < per_object * static_cast<int>(objects); ++i) {
      const uint32_t k = i % objects;
      tris.push_back({centres[k] + unit_cube(rng), 0.2 * unit_cube(rng), 0.2 * unit_cube(rng)});
      object_of.push_back(k);
    }
  }
};

// The 4-wide BVH of `tree` over `tris` finds brute force's nearest hit for random rays.
void expect_hits_match_brute_force(const BinaryBvh& tree, const std::vector<TrianglePrim>& tris, Rng& rng) {
  TriangleSoup soup;
  soup.tris = tris;
  soup.bvh.build_from_tree(tree);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    // Aimed near a random triangle, so that most rays hit something.
    const Vec3 o = 30.0 * unit_cube(rng);
    const Vec3 target = tris[static_cast<size_t>(rng.uniform() * tris.size())].v0 + 0.3 * unit_cube(rng);
    const Ray r{o, glm::normalize(target - o)};
    const auto a = soup.bvh_hit(r), b = soup.brute_hit(r);
    ASSERT_EQ(a.first, b.first) << "ray " << i;
    hits += b.second >= 0;
  }
  EXPECT_GT(hits, 500) << "test rays should hit something";
}

TEST(ObjectBvh, JoinsObjectsIntoOneValidTreeWithEachObjectsSlotsTogether) {
  Rng rng(3, 1, 4);
  const Clusters c(rng, 7, 500);
  ObjectBvh bvh;
  const std::vector<Aabb> boxes = triangle_boxes(c.tris);
  bvh.build(boxes, c.object_of, c.objects);
  const BinaryBvh tree = bvh.joined();
  expect_valid_binary_tree(tree, boxes);
  for (uint32_t k = 0; k < c.objects; ++k) {
    EXPECT_EQ(bvh.slot_count(k), 500u);
    for (uint32_t s = bvh.first_slot(k); s < bvh.first_slot(k) + bvh.slot_count(k); ++s)
      ASSERT_EQ(c.object_of[bvh.order()[s]], k) << "slot " << s;
  }
  expect_hits_match_brute_force(tree, c.tris, rng);
}

// Moving one object (a rotation and a long translation) and refitting gives a tree as valid as a
// fresh build over the moved triangles, with the same hits.
TEST(ObjectBvh, ARefittedObjectKeepsTheTreeValidAndExact) {
  Rng rng(5, 9, 2);
  Clusters c(rng, 5, 400);
  ObjectBvh bvh;
  bvh.build(triangle_boxes(c.tris), c.object_of, c.objects);
  const uint32_t moved = 2;
  auto turn = [](const Vec3& v) { return Vec3(-v.y, v.x, v.z); };
  for (size_t i = 0; i < c.tris.size(); ++i)
    if (c.object_of[i] == moved) {
      TrianglePrim& t = c.tris[i];
      t = TrianglePrim{turn(t.v0) + Vec3(0.0, 0.0, 25.0), turn(t.e1), turn(t.e2)};
    }
  const std::vector<Aabb> boxes = triangle_boxes(c.tris);
  std::vector<Aabb> slot_boxes;
  for (uint32_t s = bvh.first_slot(moved); s < bvh.first_slot(moved) + bvh.slot_count(moved); ++s)
    slot_boxes.push_back(boxes[bvh.order()[s]]);
  bvh.refit(moved, slot_boxes);
  const BinaryBvh tree = bvh.joined();
  expect_valid_binary_tree(tree, boxes);
  EXPECT_GT(tree.nodes[0].box.hi.z, 24.0);  // the moved object is inside the root's box
  expect_hits_match_brute_force(tree, c.tris, rng);
}

// Thousands of one-triangle objects along a line of geometrically growing gaps (a lopsided top
// tree): the joined tree stays within the depth the traversal stacks hold.
TEST(ObjectBvh, ManyObjectsStayWithinTheTraversalDepth) {
  std::vector<TrianglePrim> tris;
  std::vector<uint32_t> object_of;
  double x = 0.0;
  for (uint32_t k = 0; k < 3000; ++k) {
    tris.push_back({Vec3(x, 0.0, 0.0), Vec3(1e-3, 0.0, 0.0), Vec3(0.0, 1e-3, 0.0)});
    object_of.push_back(k);
    x += 1e-3 * std::pow(1.01, k);
  }
  ObjectBvh bvh;
  const std::vector<Aabb> boxes = triangle_boxes(tris);
  bvh.build(boxes, object_of, 3000);
  const BinaryBvh tree = bvh.joined();
  EXPECT_LE(expect_valid_binary_tree(tree, boxes), kMaxBvhDepth);
}

// Objects 1 and 3 of five dropped and a new one added after them: a rebuild told to reuse the three kept
// objects' subtrees builds only the new one's, and the tree is as valid and exact as a fresh build's.
// A subtree offered for another number of primitives is built again.
TEST(ObjectBvh, ARebuildReusesTheSubtreesOfUnchangedObjects) {
  Rng rng(7, 2, 9);
  const Clusters before(rng, 5, 300);
  ObjectBvh bvh;
  EXPECT_EQ(bvh.build(triangle_boxes(before.tris), before.object_of, before.objects), 5u);
  const Clusters fresh(rng, 1, 200);
  std::vector<TrianglePrim> tris;
  std::vector<uint32_t> object_of;
  const uint32_t renumbered[] = {0, 9, 1, 9, 2};  // 9: dropped
  for (size_t i = 0; i < before.tris.size(); ++i)
    if (renumbered[before.object_of[i]] != 9) {
      tris.push_back(before.tris[i]);
      object_of.push_back(renumbered[before.object_of[i]]);
    }
  for (const TrianglePrim& t : fresh.tris) {
    tris.push_back(t);
    object_of.push_back(3);
  }
  const std::vector<Aabb> boxes = triangle_boxes(tris);
  EXPECT_EQ(bvh.build(boxes, object_of, 4, {0, 2, 4, -1}), 1u);
  const BinaryBvh tree = bvh.joined();
  expect_valid_binary_tree(tree, boxes);
  for (uint32_t k = 0; k < 4; ++k)
    for (uint32_t s = bvh.first_slot(k); s < bvh.first_slot(k) + bvh.slot_count(k); ++s)
      ASSERT_EQ(object_of[bvh.order()[s]], k) << "slot " << s;
  expect_hits_match_brute_force(tree, tris, rng);

  ObjectBvh other;
  other.build(boxes, object_of, 4);
  std::vector<uint32_t> fewer = object_of;
  fewer.back() = 2;  // object 2 gains a primitive: its old subtree does not fit
  EXPECT_EQ(other.build(boxes, fewer, 4, {0, 1, 2, 3}), 2u);
  expect_valid_binary_tree(other.joined(), boxes);
  EXPECT_THROW(other.build(boxes, fewer, 4, {0, 1}), std::invalid_argument);
}

TEST(ObjectBvh, RefusesAnObjectWithoutPrimitivesAndAWrongBoxCount) {
  ObjectBvh bvh;
  const std::vector<Aabb> boxes{Aabb{Vec3(0.0), Vec3(1.0)}};
  EXPECT_THROW(bvh.build(boxes, {1}, 2), std::invalid_argument);
  bvh.build(boxes, {0}, 1);
  EXPECT_THROW(bvh.refit(0, {}), std::invalid_argument);
}

}  // namespace
}  // namespace ppm
