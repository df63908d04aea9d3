// Collapse of the binary SAH tree into the 4-wide BVH (see bvh.h).
#include "geometry/bvh.h"

#include "geometry/bvh_build.h"
#include "math/float_bounds.h"

#include <cfloat>
#include <cmath>
#include <limits>

namespace ppm {
namespace {

constexpr float kFloatInf = std::numeric_limits<float>::infinity();

class Collapser {
 public:
  Collapser(const BinaryBvh& tree, HugePageVector<BvhNode>& nodes) : tree_(tree), nodes_(nodes) {}

  // Emits a 4-wide node for binary node `b`, then its inner children.
  uint32_t emit(uint32_t b) {
    // Greedily open the inner child with the largest surface area until
    // there are four: the children most rays would enter anyway are the
    // ones worth replacing by their own children.
    uint32_t kids[4];
    int n = 0;
    if (tree_.nodes[b].is_leaf()) {
      kids[n++] = b;  // a single-leaf tree: the root holds the leaf
    } else {
      kids[n++] = b + 1;
      kids[n++] = tree_.nodes[b].first;
    }
    while (n < 4) {
      int widest = -1;
      double area = -1.0;
      for (int k = 0; k < n; ++k) {
        const BinaryBvhNode& c = tree_.nodes[kids[k]];
        if (!c.is_leaf() && c.box.half_area() > area) {
          area = c.box.half_area();
          widest = k;
        }
      }
      if (widest < 0) break;
      const uint32_t open = kids[widest];
      kids[widest] = open + 1;
      kids[n++] = tree_.nodes[open].first;
    }

    const uint32_t index = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    BvhNode& node = nodes_[index];
    for (int k = 0; k < 4; ++k) {
      for (int a = 0; a < 3; ++a) {
        node.box[2 * a][k] = kFloatInf;
        node.box[2 * a + 1][k] = -kFloatInf;
      }
      node.child[k] = 0;
      node.count[k] = 0;
    }
    for (int k = 0; k < n; ++k) {
      const BinaryBvhNode& c = tree_.nodes[kids[k]];
      for (int a = 0; a < 3; ++a) {
        node.box[2 * a][k] = float_down(c.box.lo[a]);
        node.box[2 * a + 1][k] = float_up(c.box.hi[a]);
      }
      if (c.is_leaf()) {
        node.child[k] = c.first;
        node.count[k] = c.count;
      }
    }
    for (int k = 0; k < n; ++k) {
      if (tree_.nodes[kids[k]].is_leaf()) continue;
      const uint32_t child = emit(kids[k]);  // may reallocate nodes_
      nodes_[index].child[k] = child;
    }
    return index;
  }

 private:
  const BinaryBvh& tree_;
  HugePageVector<BvhNode>& nodes_;
};

}  // namespace

BvhRay::BvhRay(const Vec3& origin, const Vec3& dir) {
  in_range = max_abs(origin) <= kFloatRange;
  for (int a = 0; a < 3; ++a) {
    const bool positive = !std::signbit(dir[a]);
    // A zero or tiny component gives +-inf (by its sign), handled in the slab test.
    const double inv_d = 1.0 / dir[a];
    const float inv_f = std::fabs(inv_d) <= FLT_MAX ? static_cast<float>(inv_d) : (positive ? kFloatInf : -kFloatInf);
    constexpr uint32_t kRow = sizeof(BvhNode::box[0]);
    near[a] = (2 * a + (positive ? 0 : 1)) * kRow;
    far[a] = (2 * a + (positive ? 1 : 0)) * kRow;
    // Entry distances must not come out too large: moving towards +a that
    // means an origin no smaller than the true one; exit distances the reverse.
    // Both roundings, then a pick by index: the sign is random per ray.
    const float rounded[2] = {float_above(origin[a]), float_below(origin[a])};
    for (int k = 0; k < 4; ++k) {
      inv[a][k] = inv_f;
      org_near[a][k] = rounded[positive ? 0 : 1];
      org_far[a][k] = rounded[positive ? 1 : 0];
    }
  }
}

void Bvh::build(const std::vector<Aabb>& boxes) { build_from_tree(build_binary_bvh(boxes, kBinaryLeafSize)); }

void Bvh::build_from_tree(BinaryBvh tree) {
  nodes_.clear();
  bounds_ = Aabb{};
  in_float_range_ = true;
  prim_order_ = std::move(tree.order);
  slots_ = static_cast<uint32_t>(prim_order_.size());
  if (tree.nodes.empty()) return;
  bounds_ = tree.nodes[0].box;
  in_float_range_ = max_abs(bounds_.lo) <= kFloatRange && max_abs(bounds_.hi) <= kFloatRange;
  nodes_.reserve(tree.nodes.size() / 2 + 1);  // at most this many; a third of it is typical
  Collapser(tree, nodes_).emit(0);
  nodes_.shrink_to_fit();
}

}  // namespace ppm
