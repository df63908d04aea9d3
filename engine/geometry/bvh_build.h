// Binned SAH build (Wald 2007) of a binary BVH over primitive boxes, in
// double precision. The result is only an intermediate: Bvh collapses it into
// its 4-wide float-box nodes (see bvh.h).
#pragma once

#include "math/aabb.h"

#include <cstdint>
#include <vector>

namespace ppm {

struct BinaryBvhNode {
  Aabb box;
  uint32_t first;  // leaf: first index into order; inner: index of the right child (left is next)
  uint32_t count;  // leaf: primitive count; inner: 0
  bool is_leaf() const { return count > 0; }
};

struct BinaryBvh {
  std::vector<BinaryBvhNode> nodes;  // depth-first, root at 0
  std::vector<uint32_t> order;       // primitive indices, each leaf's contiguous
};

// Boxes must be finite (throws std::invalid_argument otherwise); an empty
// input gives an empty tree. Leaves hold at most `max_leaf` primitives unless
// the depth limit forces more.
BinaryBvh build_binary_bvh(const std::vector<Aabb>& boxes, uint32_t max_leaf);

}  // namespace ppm
