// Bounding volume hierarchy over primitive boxes, built with binned SAH
// (Wald 2007) and stored as a flat array of 32-byte-aligned nodes in depth-first
// order (left child follows its parent). Traversal is a template over the
// caller's primitive test so the scene dispatches on primitive kind without
// virtual calls.
#pragma once

#include "math/aabb.h"

#include <cstdint>
#include <vector>

namespace ppm {

struct BvhNode {
  Aabb box;
  uint32_t first;  // leaf: first index into prim_order; inner: index of the right child
  uint32_t count;  // leaf: primitive count; inner: 0
  bool is_leaf() const { return count > 0; }
};

class Bvh {
 public:
  // Builds over `boxes` (one per primitive). Boxes must be finite.
  void build(const std::vector<Aabb>& boxes);

  const std::vector<BvhNode>& nodes() const { return nodes_; }
  const std::vector<uint32_t>& prim_order() const { return prim_order_; }
  Aabb bounds() const { return nodes_.empty() ? Aabb{} : nodes_[0].box; }

  // Closest-hit traversal. `test(prim, tmax)` intersects one primitive and,
  // on a closer hit, lowers tmax and returns true.
  template <class Test>
  void closest(const Vec3& origin, const Vec3& dir, double& tmax, Test&& test) const;

  // Any-hit traversal for shadow rays: true as soon as `test(prim, tmax)` reports a hit.
  template <class Test>
  bool any(const Vec3& origin, const Vec3& dir, double tmax, Test&& test) const;

 private:
  uint32_t build_node(const std::vector<Aabb>& boxes, const std::vector<Vec3>& centers,
                      uint32_t begin, uint32_t end, int depth);

  std::vector<BvhNode> nodes_;
  std::vector<uint32_t> prim_order_;
};

inline Vec3 safe_inverse(const Vec3& d) {
  // Zero components become huge finite values of the right sign, not inf, so
  // 0 * inv never yields NaN in the slab test.
  auto inv = [](double x) { return std::fabs(x) > 1e-300 ? 1.0 / x : std::copysign(1e300, x); };
  return Vec3(inv(d.x), inv(d.y), inv(d.z));
}

template <class Test>
void Bvh::closest(const Vec3& origin, const Vec3& dir, double& tmax, Test&& test) const {
  if (nodes_.empty()) return;
  const Vec3 inv = safe_inverse(dir);
  uint32_t stack[64];
  int top = 0;
  uint32_t node = 0;
  if (slab_entry(nodes_[0].box, origin, inv, tmax) == kInf) return;
  for (;;) {
    const BvhNode& n = nodes_[node];
    if (n.is_leaf()) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) test(prim_order_[i], tmax);
    } else {
      uint32_t a = node + 1, b = n.first;
      double ta = slab_entry(nodes_[a].box, origin, inv, tmax);
      double tb = slab_entry(nodes_[b].box, origin, inv, tmax);
      if (ta > tb) {
        std::swap(a, b);
        std::swap(ta, tb);
      }
      if (ta != kInf) {
        if (tb != kInf) stack[top++] = b;
        node = a;
        continue;
      }
    }
    // Pop, skipping nodes that a closer hit has since ruled out.
    for (;;) {
      if (top == 0) return;
      node = stack[--top];
      if (slab_entry(nodes_[node].box, origin, inv, tmax) != kInf) break;
    }
  }
}

template <class Test>
bool Bvh::any(const Vec3& origin, const Vec3& dir, double tmax, Test&& test) const {
  if (nodes_.empty()) return false;
  const Vec3 inv = safe_inverse(dir);
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& n = nodes_[stack[--top]];
    if (slab_entry(n.box, origin, inv, tmax) == kInf) continue;
    if (n.is_leaf()) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        double t = tmax;
        if (test(prim_order_[i], t)) return true;
      }
    } else {
      stack[top++] = n.first;
      stack[top++] = static_cast<uint32_t>(&n - nodes_.data()) + 1;
    }
  }
  return false;
}

}  // namespace ppm
