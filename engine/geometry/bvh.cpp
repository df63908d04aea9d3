// Collapse of the binary SAH tree into the 4-wide BVH (see bvh.h).
#include "geometry/bvh.h"

#include "geometry/bvh_build.h"
#include "math/float_bounds.h"
#include "base/parallel.h"

#include <cfloat>
#include <cmath>
#include <limits>

namespace ppm {
namespace {

constexpr float kFloatInf = std::numeric_limits<float>::infinity();

// Binary subtrees the collapse emits on their own (in parallel), and where each one's root goes.
struct DeferredSubtree {
  uint32_t binary;  // its root in the binary tree
  uint32_t end;     // one past its last binary node (the tree is depth-first)
  uint32_t parent;  // the 4-wide node that points at it ...
  int slot;         // ... in this child slot
};

class Collapser {
 public:
  explicit Collapser(const BinaryBvh& tree) : tree_(tree) {}

  // Emits into `out` a 4-wide node for binary node `b` (whose subtree ends before binary node
  // `end`), then its inner children. Given `deferred`, inner children kDeferredDepth levels below
  // the first node are left to it instead.
  uint32_t emit(uint32_t b, uint32_t end, HugePageVector<BvhNode>& out, int depth = 0,
                std::vector<DeferredSubtree>* deferred = nullptr) const {
    uint32_t kids[4], ends[4];
    const int n = open_children(b, end, kids, ends);
    const uint32_t index = static_cast<uint32_t>(out.size());
    out.push_back(node_of(kids, n));
    for (int k = 0; k < n; ++k) {
      if (tree_.nodes[kids[k]].is_leaf()) continue;
      if (deferred && depth + 1 >= kDeferredDepth) {
        deferred->push_back(DeferredSubtree{kids[k], ends[k], index, k});
        continue;
      }
      const uint32_t child = emit(kids[k], ends[k], out, depth + 1, deferred);  // may reallocate out
      out[index].child[k] = child;
    }
    return index;
  }

  // 4-wide levels emitted before the rest is deferred: up to 4^2 subtrees for the threads to share.
  static constexpr int kDeferredDepth = 2;

 private:
  // Greedily opens the inner child with the largest surface area until there are four: the
  // children most rays would enter anyway are the ones worth replacing by their own children.
  // Returns how many children `b` gets; kids/ends: their binary nodes and subtree ends.
  int open_children(uint32_t b, uint32_t end, uint32_t (&kids)[4], uint32_t (&ends)[4]) const {
    int n = 0;
    if (tree_.nodes[b].is_leaf()) {
      kids[0] = b;  // a single-leaf tree: the root holds the leaf
      ends[0] = end;
      return 1;
    }
    kids[n] = b + 1, ends[n++] = tree_.nodes[b].first;
    kids[n] = tree_.nodes[b].first, ends[n++] = end;
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
      kids[n] = tree_.nodes[open].first, ends[n++] = ends[widest];
      kids[widest] = open + 1, ends[widest] = tree_.nodes[open].first;
    }
    return n;
  }

  // The node over binary nodes kids[0, n): their boxes, and leaf children's slots; inner children's
  // indices are the caller's to set.
  BvhNode node_of(const uint32_t (&kids)[4], int n) const {
    BvhNode node;
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
        node.box[2 * a][k] = c.box.lo[a];
        node.box[2 * a + 1][k] = c.box.hi[a];
      }
      if (c.is_leaf()) {
        node.child[k] = c.first;
        node.count[k] = c.count;
      }
    }
    return node;
  }

  const BinaryBvh& tree_;
};

// Appends `part` (a subtree emitted on its own, its root at 0) at `offset` of `nodes`.
void place_subtree(const HugePageVector<BvhNode>& part, uint32_t offset, HugePageFillVector<BvhNode>& nodes) {
  for (size_t i = 0; i < part.size(); ++i) {
    BvhNode node = part[i];
    for (int k = 0; k < 4; ++k)
      if (node.count[k] == 0 && node.child[k] != 0) node.child[k] += offset;  // an inner child
    nodes[offset + i] = node;
  }
}

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

void Bvh::build(size_t count, const std::function<Aabb(size_t)>& box_of) {
  build_from_tree(build_binary_bvh(count, box_of, kBinaryLeafSize));
}

void Bvh::build_from_tree(BinaryBvh tree) {
  HugePageFillVector<BvhNode>().swap(nodes_);  // sized to this tree below, not to a larger earlier one
  bounds_ = Aabb{};
  in_float_range_ = true;
  prim_order_ = std::move(tree.order);
  slots_ = static_cast<uint32_t>(prim_order_.size());
  if (tree.nodes.empty()) return;
  bounds_ = tree.nodes[0].box.to_double();
  in_float_range_ = max_abs(bounds_.lo) <= kFloatRange && max_abs(bounds_.hi) <= kFloatRange;
  collapse(tree);
}

// The top levels on this thread, then their subtrees on all threads, each into a list of its own
// (a binary subtree of k nodes makes at most k/2 4-wide nodes; a third is typical); then the lists
// are placed after the top, in order, so the layout does not depend on which thread ran what.
// Small trees (a dynamic scene's objects) stay on this thread.
void Bvh::collapse(const BinaryBvh& tree) {
  const Collapser collapser(tree);
  const uint32_t size = static_cast<uint32_t>(tree.nodes.size());
  HugePageVector<BvhNode> top;
  std::vector<DeferredSubtree> deferred;
  constexpr uint32_t kParallelNodes = 1u << 17;
  collapser.emit(0, size, top, 0, size >= kParallelNodes ? &deferred : nullptr);
  std::vector<HugePageVector<BvhNode>> parts(deferred.size());
  if (!deferred.empty())  // (parallel_each starts a thread even for nothing)
    parallel_each(hardware_threads(), deferred.size(), [&](size_t i) {
      parts[i].reserve((deferred[i].end - deferred[i].binary) / 2 + 1);
      collapser.emit(deferred[i].binary, deferred[i].end, parts[i]);
    });
  std::vector<uint32_t> offset(parts.size());
  size_t total = top.size();
  for (size_t i = 0; i < parts.size(); ++i) {
    offset[i] = static_cast<uint32_t>(total);
    total += parts[i].size();
    top[deferred[i].parent].child[deferred[i].slot] = offset[i];
  }
  nodes_.resize(total);  // unwritten (HugePageFillVector): the copies' page faults on every thread
  std::copy(top.begin(), top.end(), nodes_.begin());
  if (!parts.empty())
    parallel_each(hardware_threads(), parts.size(), [&](size_t i) {
      place_subtree(parts[i], offset[i], nodes_);
      HugePageVector<BvhNode>().swap(parts[i]);
    });
}

}  // namespace ppm
