// Binned SAH build (Wald 2007) of a binary BVH over primitive boxes. The result is only an
// intermediate: Bvh collapses it into its 4-wide float-box nodes (see bvh.h), so the build keeps
// the boxes in float, rounded outwards (half the bytes to move), and its nodes' boxes are those
// unions: they contain the double boxes' and round to the same float boxes.
#pragma once

#include "math/aabb.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace ppm {

struct BinaryBvhNode {
  FloatAabb box;
  uint32_t first;  // leaf: first index into order; inner: index of the right child (left is next)
  uint32_t count;  // leaf: primitive count; inner: 0
  bool is_leaf() const { return count > 0; }
};

struct BinaryBvh {
  std::vector<BinaryBvhNode> nodes;  // depth-first, root at 0
  std::vector<uint32_t> order;       // primitive indices, each leaf's contiguous
};

// Leaves of the binary tree become leaf children of the 4-wide nodes (Bvh).
constexpr uint32_t kBinaryLeafSize = 4;
// A whole-scene build's depth limit (it keeps traversal stacks small and bounded).
constexpr int kMaxBuildDepth = 60;
// The deepest tree a Bvh is given: a whole-scene build, or an ObjectBvh's joined tree (a top tree of
// at most 24 levels, a chain of at most 24 over the objects a top leaf holds, then an object's
// subtree). Traversal stacks are sized by it.
constexpr int kMaxBvhDepth = 24 + 24 + kMaxBuildDepth;

// Boxes must be finite (throws std::invalid_argument otherwise); an empty
// input gives an empty tree. Leaves hold at most `max_leaf` primitives unless
// the depth limit (edges from the root) forces more.
BinaryBvh build_binary_bvh(const std::vector<Aabb>& boxes, uint32_t max_leaf, int max_depth = kMaxBuildDepth);
// The same over `count` primitives whose boxes box_of(i) gives, asked once each on the build's
// threads (so they need not be stored: 48 bytes a primitive).
BinaryBvh build_binary_bvh(size_t count, const std::function<Aabb(size_t)>& box_of, uint32_t max_leaf,
                           int max_depth = kMaxBuildDepth);

}  // namespace ppm
