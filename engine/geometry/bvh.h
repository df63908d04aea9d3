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

#include "geometry/bvh_build.h"
#include "geometry/bvh_slab.h"
#include "base/huge_pages.h"
#include "geometry/ray.h"
#include "math/aabb.h"
#include "math/float_bounds.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace ppm {

// A hint to start loading memory that will soon be read (no effect elsewhere). An asm statement
// where there is one: GCC takes __builtin_prefetch for an effect-free operation and dropped whole
// loops of them (the leaf prefetch of Scene::prefetch_leaf once it had two arrays to choose from).
inline void prefetch(const void* p) {
#if defined(__GNUC__) && defined(__x86_64__)
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#elif defined(__GNUC__) && defined(__aarch64__)
  asm volatile("prfm pldl1keep, %0" : : "Q"(*static_cast<const char*>(p)));
#elif defined(__GNUC__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

// Every cache line of the `bytes` from `begin`.
inline void prefetch_lines(const void* begin, size_t bytes) {
  const uintptr_t end = reinterpret_cast<uintptr_t>(begin) + bytes;
  for (uintptr_t p = reinterpret_cast<uintptr_t>(begin) & ~uintptr_t(63); p < end; p += 64)
    prefetch(reinterpret_cast<const void*>(p));
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
  // Builds over `count` primitives whose boxes box_of(i) gives (asked on the build's threads).
  void build(size_t count, const std::function<Aabb(size_t)>& box_of);
  // Collapses a binary tree built elsewhere (an ObjectBvh's, at most kMaxBvhDepth deep).
  void build_from_tree(BinaryBvh tree);

  const HugePageFillVector<BvhNode>& nodes() const { return nodes_; }
  // prim_order()[slot] is the primitive at a leaf slot (empty after release_prim_order).
  const std::vector<uint32_t>& prim_order() const { return prim_order_; }
  // For a caller that has laid its primitives out by slot: 4 bytes a primitive less.
  void release_prim_order() { std::vector<uint32_t>().swap(prim_order_); }
  Aabb bounds() const { return bounds_; }  // bounds of all primitives, rounded outwards to float

  // Closest-hit traversal, nearest child first. `test(slot, tmax)` intersects
  // the primitive at that slot and, on a closer hit, lowers tmax.
  // `prefetch(first, count)` is called as soon as a leaf's box is hit, before
  // the leaf is tested: the caller can start loading the leaf's data then.
  template <class Test, class Prefetch = NoPrefetch>
  void closest(const Vec3& origin, const Vec3& dir, double& tmax, Test&& test, Prefetch&& prefetch = {}) const;

  // Closest hits of many rays at once, `kInterleavedRays` walks in turn:
  // each advances by one node or leaf and then yields, so one ray's cache
  // misses are loaded while the others work. Random rays spend most of
  // their time waiting on such misses. `ray_at(i)` gives ray i (a Ray);
  // `test(i, slot, tmax)` is as in closest() for ray i, starting from
  // tmax = kInf; `done(i)` is called once ray i's closest hit is final, in
  // no particular order. Uses about 20 KB of stack (8 walks).
  template <class RayAt, class Test, class Prefetch, class Done>
  void closest_many(size_t count, RayAt&& ray_at, Test&& test, Prefetch&& prefetch, Done&& done) const;

  // Any-hit traversal for shadow rays: true as soon as `test(slot, tmax)`
  // reports a hit with t < tmax.
  template <class Test>
  bool any(const Vec3& origin, const Vec3& dir, double tmax, Test&& test) const;

  static constexpr int kInterleavedRays = 8;

 private:
  // Where a closest-hit traversal stands: the node or leaf to visit next and
  // the stack of those still to visit.
  struct ClosestWalk {
    // Back to the root; the stack's contents are left as they are (2 KB).
    void reset(double tmax) {
      tmax_f = float_up(tmax);
      top = 0;
      cur = Entry{0, 0, 0.0f};
    }
    struct Entry {
      uint32_t index, count;  // as in BvhNode: count > 0 is a leaf
      float t;                // entry distance, to skip it once a closer hit is known
    };
    float tmax_f = 0.0f;     // tmax rounded up to float, for the slab test
    int top = 0;
    Entry cur{0, 0, 0.0f};   // starts at the root
    Entry stack[3 * kMaxBvhDepth + 1];  // each level of the binary tree adds at most 3
  };

  // Visits w.cur (a node's child boxes, or a leaf's primitives) and moves to
  // the next entry; false once nothing is left to visit.
  template <class Test, class Prefetch>
  bool step(ClosestWalk& w, const BvhRay& r, double& tmax, Test&& test, Prefetch&& prefetch) const;

  void collapse(const BinaryBvh& tree);

  HugePageFillVector<BvhNode> nodes_;  // root at 0
  std::vector<uint32_t> prim_order_;
  uint32_t slots_ = 0;  // leaf slots: primitives
  Aabb bounds_;
  bool in_float_range_ = true;  // all boxes within kFloatRange (see bvh_slab.h)
};

template <class Test, class Prefetch>
void Bvh::closest(const Vec3& origin, const Vec3& dir, double& tmax, Test&& test, Prefetch&& prefetch_leaf) const {
  if (nodes_.empty()) return;
  const BvhRay r(origin, dir);
  if (!r.in_range || !in_float_range_) {  // beyond what the float slab test covers
    for (uint32_t s = 0; s < slots_; ++s) test(s, tmax);
    return;
  }
  ClosestWalk walk;
  walk.reset(tmax);
  while (step(walk, r, tmax, test, prefetch_leaf)) {
  }
}

template <class RayAt, class Test, class Prefetch, class Done>
void Bvh::closest_many(size_t count, RayAt&& ray_at, Test&& test, Prefetch&& prefetch_leaf, Done&& done) const {
  struct Lane {
    size_t ray;
    double tmax;
    BvhRay r;
    ClosestWalk walk;
  };
  Lane lanes[kInterleavedRays];
  int active = 0;
  size_t next = 0;
  // Starts the next ray that needs a walk in lane k; false when none is left.
  auto start = [&](int k) {
    for (; next < count; ++next) {
      const Ray& ray = ray_at(next);
      double tmax = kInf;
      const BvhRay r(ray.origin, ray.direction);
      if (nodes_.empty() || !r.in_range || !in_float_range_) {  // no walk: brute force, or nothing to hit
        closest(ray.origin, ray.direction, tmax, [&](uint32_t s, double& t) { return test(next, s, t); });
        done(next);
        continue;
      }
      Lane& lane = lanes[k];
      lane.ray = next++;
      lane.tmax = tmax;
      lane.r = r;
      lane.walk.reset(tmax);
      return true;
    }
    return false;
  };
  while (active < kInterleavedRays && start(active)) ++active;
  // Round robin, one node or leaf per ray and turn: by the time a ray's turn
  // comes again, the node it prefetched has had the others' work to arrive.
  while (active > 0) {
    for (int k = 0; k < active;) {
      Lane& lane = lanes[k];
      const size_t ray = lane.ray;
      auto lane_test = [&](uint32_t s, double& t) { return test(ray, s, t); };
      if (step(lane.walk, lane.r, lane.tmax, lane_test, prefetch_leaf)) {
        ++k;
        continue;
      }
      done(ray);
      if (start(k)) continue;
      if (k != --active) lanes[k] = lanes[active];  // keep the lanes in use at the front
    }
  }
}

template <class Test, class Prefetch>
bool Bvh::step(ClosestWalk& w, const BvhRay& r, double& tmax, Test&& test, Prefetch&& prefetch_leaf) const {
  if (w.cur.count == 0) {
    const BvhNode& n = nodes_[w.cur.index];
    float t[4];
    const unsigned mask = intersect_children(n, r, w.tmax_f, t);
    if (mask != 0) {
      // Push the hit children sorted so the nearest is on top, then pop it
      // to continue there. Random rays miss the cache on most nodes and
      // leaves, so each hit child's memory is requested now, in parallel.
      const int base = w.top;
      for (unsigned bits = mask; bits != 0; bits &= bits - 1) {
        const int k = lowest_bit(bits);
        const ClosestWalk::Entry e{n.child[k], n.count[k], t[k]};
        if (e.count == 0) {
          const char* p = reinterpret_cast<const char*>(&nodes_[e.index]);
          prefetch(p);
          prefetch(p + 64);
        } else {
          prefetch_leaf(e.index, e.count);
        }
        int j = w.top++;
        for (; j > base && w.stack[j - 1].t < e.t; --j) w.stack[j] = w.stack[j - 1];
        w.stack[j] = e;
      }
      w.cur = w.stack[--w.top];
      return true;
    }
  } else {
    const double before = tmax;
    for (uint32_t s = w.cur.index; s < w.cur.index + w.cur.count; ++s) test(s, tmax);
    if (tmax != before) w.tmax_f = float_up(tmax);
  }
  // Pop, skipping children that a closer hit has since ruled out.
  for (;;) {
    if (w.top == 0) return false;
    w.cur = w.stack[--w.top];
    if (w.cur.t <= w.tmax_f * kSlabSlack + kSlabTiny) return true;
  }
}

template <class Test>
bool Bvh::any(const Vec3& origin, const Vec3& dir, double tmax, Test&& test) const {
  if (nodes_.empty()) return false;
  const BvhRay r(origin, dir);
  if (!r.in_range || !in_float_range_) {  // beyond what the float slab test covers
    for (uint32_t s = 0; s < slots_; ++s) {
      double tt = tmax;
      if (test(s, tt)) return true;
    }
    return false;
  }
  const float tmax_f = float_up(tmax);
  uint32_t stack[3 * kMaxBvhDepth + 4];  // each level pops one node and pushes at most four
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
