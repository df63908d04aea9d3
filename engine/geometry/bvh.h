// Four-wide bounding volume hierarchy over primitive boxes: a binned SAH
// binary tree (bvh_build.h) collapsed so each node holds up to four children,
// whose boxes one SIMD pass tests together (structure-of-arrays layout).
//
// Boxes are stored in float rounded outward: a node is 128 bytes (two cache
// lines) where double boxes would take 224. The slab test runs in
// float too, with the rounding handled so that it never rejects a box the
// double ray touches (bvh_slab.h); the primitive test decides the final hit
// in double.
//
// Traversal is a template over the caller's primitive test so the scene
// dispatches on primitive kind without virtual calls. The test receives a
// leaf *slot*: a position in prim_order(), so callers can keep per-primitive
// data in leaf order, where a leaf's primitives are contiguous in memory.
#pragma once

#include "geometry/bvh_slab.h"
#include "geometry/huge_pages.h"
#include "math/aabb.h"
#include "math/float_bounds.h"

#include <cstdint>
#include <vector>

namespace ppm {

// A hint to start loading memory that will soon be read (no effect elsewhere).
inline void prefetch(const void* p) {
#if defined(__GNUC__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

// Index of the lowest set bit of a non-zero mask.
inline int lowest_bit(unsigned mask) {
#if defined(__GNUC__)
  return __builtin_ctz(mask);
#else
  int k = 0;
  while (!(mask >> k & 1u)) ++k;
  return k;
#endif
}

struct NoPrefetch {
  void operator()(uint32_t, uint32_t) const {}
};

class Bvh {
 public:
  // Builds over `boxes` (one per primitive). Boxes must be finite.
  void build(const std::vector<Aabb>& boxes);

  const HugePageVector<BvhNode>& nodes() const { return nodes_; }
  // prim_order()[slot] is the primitive at a leaf slot.
  const std::vector<uint32_t>& prim_order() const { return prim_order_; }
  Aabb bounds() const { return bounds_; }  // exact (double) bounds of all primitives

  // Closest-hit traversal, nearest child first. `test(slot, tmax)` intersects
  // the primitive at that slot and, on a closer hit, lowers tmax.
  // `prefetch(first, count)` is called as soon as a leaf's box is hit, before
  // the leaf is tested: the caller can start loading the leaf's data then.
  template <class Test, class Prefetch = NoPrefetch>
  void closest(const Vec3& origin, const Vec3& dir, double& tmax, Test&& test, Prefetch&& prefetch = {}) const;

  // Any-hit traversal for shadow rays: true as soon as `test(slot, tmax)`
  // reports a hit with t < tmax.
  template <class Test>
  bool any(const Vec3& origin, const Vec3& dir, double tmax, Test&& test) const;

 private:
  HugePageVector<BvhNode> nodes_;  // root at 0
  std::vector<uint32_t> prim_order_;
  Aabb bounds_;
  bool in_float_range_ = true;  // all boxes within kFloatRange (see bvh_slab.h)
};

template <class Test, class Prefetch>
void Bvh::closest(const Vec3& origin, const Vec3& dir, double& tmax, Test&& test, Prefetch&& prefetch_leaf) const {
  if (nodes_.empty()) return;
  const BvhRay r(origin, dir);
  if (!r.in_range || !in_float_range_) {  // beyond what the float slab test covers
    for (uint32_t s = 0; s < prim_order_.size(); ++s) test(s, tmax);
    return;
  }
  float tmax_f = float_up(tmax);
  struct Entry {
    uint32_t index, count;  // as in BvhNode: count > 0 is a leaf
    float t;                // entry distance, to skip it once a closer hit is known
  };
  Entry stack[3 * 64 + 1];  // the binary tree is at most 60 deep; each level adds at most 3
  int top = 0;
  Entry cur{0, 0, 0.0f};
  for (;;) {
    if (cur.count == 0) {
      const BvhNode& n = nodes_[cur.index];
      float t[4];
      const unsigned mask = intersect_children(n, r, tmax_f, t);
      if (mask != 0) {
        // Push the hit children sorted so the nearest is on top, then pop it
        // to continue there. Random rays miss the cache on most nodes and
        // leaves, so each hit child's memory is requested now, in parallel.
        const int base = top;
        for (unsigned bits = mask; bits != 0; bits &= bits - 1) {
          const int k = lowest_bit(bits);
          const Entry e{n.child[k], n.count[k], t[k]};
          if (e.count == 0) {
            const char* p = reinterpret_cast<const char*>(&nodes_[e.index]);
            prefetch(p);
            prefetch(p + 64);
          } else {
            prefetch_leaf(e.index, e.count);
          }
          int j = top++;
          for (; j > base && stack[j - 1].t < e.t; --j) stack[j] = stack[j - 1];
          stack[j] = e;
        }
        cur = stack[--top];
        continue;
      }
    } else {
      const double before = tmax;
      for (uint32_t s = cur.index; s < cur.index + cur.count; ++s) test(s, tmax);
      if (tmax != before) tmax_f = float_up(tmax);
    }
    // Pop, skipping children that a closer hit has since ruled out.
    for (;;) {
      if (top == 0) return;
      cur = stack[--top];
      if (cur.t <= tmax_f * kSlabSlack + kSlabTiny) break;
    }
  }
}

template <class Test>
bool Bvh::any(const Vec3& origin, const Vec3& dir, double tmax, Test&& test) const {
  if (nodes_.empty()) return false;
  const BvhRay r(origin, dir);
  if (!r.in_range || !in_float_range_) {  // beyond what the float slab test covers
    for (uint32_t s = 0; s < prim_order_.size(); ++s) {
      double tt = tmax;
      if (test(s, tt)) return true;
    }
    return false;
  }
  const float tmax_f = float_up(tmax);
  uint32_t stack[3 * 64 + 4];  // each level pops one node and pushes at most four
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& n = nodes_[stack[--top]];
    float t[4];
    for (unsigned bits = intersect_children(n, r, tmax_f, t); bits != 0; bits &= bits - 1) {
      const int k = lowest_bit(bits);
      if (n.count[k] == 0) {
        stack[top++] = n.child[k];
        continue;
      }
      for (uint32_t s = n.child[k]; s < n.child[k] + n.count[k]; ++s) {
        double tt = tmax;
        if (test(s, tt)) return true;
      }
    }
  }
  return false;
}

}  // namespace ppm
