// The object-by-object BVH (see object_bvh.h).
#include "geometry/object_bvh.h"

#include <stdexcept>

namespace ppm {
namespace {

constexpr int kTopDepth = 24;  // see kMaxBvhDepth

}  // namespace

uint32_t ObjectBvh::build(const std::vector<Aabb>& boxes, const std::vector<uint32_t>& object_of, uint32_t objects,
                          const std::vector<int32_t>& reuse) {
  if (!reuse.empty() && reuse.size() != objects) throw std::invalid_argument("BVH: one reuse entry per object expected");
  std::vector<std::vector<uint32_t>> members(objects);
  for (uint32_t i = 0; i < object_of.size(); ++i) members.at(object_of[i]).push_back(i);
  std::vector<Object> previous = std::move(objects_);
  objects_.assign(objects, Object{});
  order_.clear();
  order_.reserve(boxes.size());
  std::vector<Aabb> own;
  uint32_t built = 0;
  for (uint32_t o = 0; o < objects; ++o) {
    if (members[o].empty()) throw std::invalid_argument("BVH: an object without primitives");
    Object& object = objects_[o];
    const int32_t old = reuse.empty() ? -1 : reuse[o];
    if (old >= 0 && static_cast<size_t>(old) < previous.size() && previous[old].tree.order.size() == members[o].size()) {
      object.tree = std::move(previous[old].tree);
    } else {
      own.clear();
      for (uint32_t i : members[o]) own.push_back(boxes[i]);
      object.tree = build_binary_bvh(own, kBinaryLeafSize);
      ++built;
    }
    object.first_slot = static_cast<uint32_t>(order_.size());
    for (uint32_t k : object.tree.order) order_.push_back(members[o][k]);
  }
  return built;
}

// Depth-first layout: both children of node i come after it, so a backward sweep sees them first.
void ObjectBvh::refit(uint32_t object, const std::vector<Aabb>& slot_boxes) {
  BinaryBvh& tree = objects_.at(object).tree;
  if (slot_boxes.size() != tree.order.size()) throw std::invalid_argument("BVH refit: one box per slot expected");
  for (size_t i = tree.nodes.size(); i-- > 0;) {
    BinaryBvhNode& n = tree.nodes[i];
    n.box = FloatAabb{};
    if (n.is_leaf()) {
      for (uint32_t k = n.first; k < n.first + n.count; ++k) n.box.grow(FloatAabb::around(slot_boxes[k]));
    } else {
      n.box.grow(tree.nodes[i + 1].box);
      n.box.grow(tree.nodes[n.first].box);
    }
  }
}

BinaryBvh ObjectBvh::joined() const {
  BinaryBvh out;
  if (objects_.empty()) return out;
  std::vector<Aabb> roots;
  roots.reserve(objects_.size());
  size_t nodes = 0;
  for (const Object& o : objects_) {
    roots.push_back(o.tree.nodes[0].box.to_double());
    nodes += o.tree.nodes.size();
  }
  const BinaryBvh top = build_binary_bvh(roots, 1, kTopDepth);
  out.nodes.reserve(nodes + top.nodes.size());
  append_top(top, 0, out);
  out.order = order_;
  return out;
}

size_t ObjectBvh::memory_bytes() const {
  size_t bytes = order_.capacity() * sizeof(uint32_t) + objects_.capacity() * sizeof(Object);
  for (const Object& o : objects_)
    bytes += o.tree.nodes.capacity() * sizeof(BinaryBvhNode) + o.tree.order.capacity() * sizeof(uint32_t);
  return bytes;
}

uint32_t ObjectBvh::append_top(const BinaryBvh& top, uint32_t top_node, BinaryBvh& out) const {
  const BinaryBvhNode& n = top.nodes[top_node];
  if (n.is_leaf()) return append_objects(top, n.first, n.count, out);
  const uint32_t index = static_cast<uint32_t>(out.nodes.size());
  out.nodes.push_back(BinaryBvhNode{n.box, 0, 0});
  append_top(top, top_node + 1, out);
  const uint32_t right = append_top(top, n.first, out);
  out.nodes[index].first = right;
  return index;
}

// A top leaf holds one object unless the top's depth limit forced more: those are split in halves
// (at most 24 levels for 2^24 objects).
uint32_t ObjectBvh::append_objects(const BinaryBvh& top, uint32_t first, uint32_t count, BinaryBvh& out) const {
  const uint32_t index = static_cast<uint32_t>(out.nodes.size());
  if (count > 1) {
    FloatAabb box;
    for (uint32_t k = first; k < first + count; ++k) box.grow(objects_[top.order[k]].tree.nodes[0].box);
    out.nodes.push_back(BinaryBvhNode{box, 0, 0});
    const uint32_t half = count / 2;
    append_objects(top, first, half, out);
    out.nodes[index].first = append_objects(top, first + half, count - half, out);
    return index;
  }
  const Object& object = objects_[top.order[first]];
  for (BinaryBvhNode node : object.tree.nodes) {
    node.first += node.is_leaf() ? object.first_slot : index;
    out.nodes.push_back(node);
  }
  return index;
}

}  // namespace ppm
