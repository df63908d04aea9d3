// A BVH built object by object, for scenes whose objects move while they render (the viewport, as
// Cycles' "dynamic BVH" there): each object's primitives get a binary subtree of their own, and a
// tree over the objects' boxes joins them. An object moved or reshaped in place refits its own
// subtree, and the top is built again (objects are few), so an edit costs a pass over one object's
// nodes and a collapse (Bvh::build_from_tree) instead of a build of the whole scene. Objects added,
// removed or given other primitives are built again with the others' subtrees kept (build's `reuse`).
// A whole-scene build (Bvh::build(boxes)) traces faster where objects overlap; final renders use that one.
#pragma once

#include "geometry/bvh_build.h"
#include "math/aabb.h"

#include <cstdint>
#include <vector>

namespace ppm {

class ObjectBvh {
 public:
  // `object_of[i]`: the object (0 .. objects - 1) of primitive i, whose box is boxes[i]. Every object
  // must have a primitive. `reuse[o]` (empty: none): the object of the previous build whose subtree
  // object o takes over, its primitives the same and in the same order, or -1 to build its own. A
  // subtree over another number of primitives is built again. Returns how many subtrees were built.
  uint32_t build(const std::vector<Aabb>& boxes, const std::vector<uint32_t>& object_of, uint32_t objects,
                 const std::vector<int32_t>& reuse = {});

  // The primitive at each leaf slot: an object's primitives take contiguous slots, objects in order.
  const std::vector<uint32_t>& order() const { return order_; }
  uint32_t object_count() const { return static_cast<uint32_t>(objects_.size()); }
  uint32_t first_slot(uint32_t object) const { return objects_[object].first_slot; }
  uint32_t slot_count(uint32_t object) const { return static_cast<uint32_t>(objects_[object].tree.order.size()); }

  // Object `object`'s primitives changed their boxes: slot_boxes[k] is the new box of the primitive
  // at slot first_slot(object) + k. Its subtree keeps its shape.
  void refit(uint32_t object, const std::vector<Aabb>& slot_boxes);

  // The binary tree over all slots: a tree over the objects' boxes whose leaves are the objects'
  // subtrees. Its order is order().
  BinaryBvh joined() const;
  size_t memory_bytes() const;

 private:
  struct Object {
    BinaryBvh tree;  // its order: positions among the object's own slots
    uint32_t first_slot;
  };
  // Appends the subtree of the top tree's node `top_node` to `out`; returns its index there.
  uint32_t append_top(const BinaryBvh& top, uint32_t top_node, BinaryBvh& out) const;
  // Appends the objects `top.order[first, first + count)` (each a subtree) as one subtree.
  uint32_t append_objects(const BinaryBvh& top, uint32_t first, uint32_t count, BinaryBvh& out) const;

  std::vector<Object> objects_;
  std::vector<uint32_t> order_;
};

}  // namespace ppm
