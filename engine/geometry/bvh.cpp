// Binned SAH build of the BVH (see bvh.h).
#include "geometry/bvh.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace ppm {
namespace {

constexpr int kBins = 16;
constexpr uint32_t kMaxLeaf = 4;
constexpr int kMaxDepth = 60;  // traversal stack holds 64

struct Bin {
  Aabb box;
  uint32_t count = 0;
};

}  // namespace

void Bvh::build(const std::vector<Aabb>& boxes) {
  nodes_.clear();
  prim_order_.resize(boxes.size());
  std::iota(prim_order_.begin(), prim_order_.end(), 0u);
  if (boxes.empty()) return;
  std::vector<Vec3> centers(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (!is_finite(boxes[i].lo) || !is_finite(boxes[i].hi))
      throw std::invalid_argument("BVH: primitive " + std::to_string(i) + " has a non-finite bounding box");
    centers[i] = boxes[i].center();
  }
  nodes_.reserve(2 * boxes.size() / kMaxLeaf + 2);
  build_node(boxes, centers, 0, static_cast<uint32_t>(boxes.size()), 0);
}

uint32_t Bvh::build_node(const std::vector<Aabb>& boxes, const std::vector<Vec3>& centers,
                         uint32_t begin, uint32_t end, int depth) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(BvhNode{});
  Aabb box, cbox;
  for (uint32_t i = begin; i < end; ++i) {
    box.grow(boxes[prim_order_[i]]);
    cbox.grow(centers[prim_order_[i]]);
  }
  nodes_[index].box = box;
  const uint32_t count = end - begin;
  auto make_leaf = [&]() {
    nodes_[index].first = begin;
    nodes_[index].count = count;
    return index;
  };
  const int axis = cbox.longest_axis();
  const double lo = cbox.lo[axis], extent = cbox.hi[axis] - cbox.lo[axis];
  if (count <= kMaxLeaf || depth >= kMaxDepth) return make_leaf();
  if (!(extent > 0.0)) {
    // All centroids coincide: SAH cannot separate them; halve by index so the
    // tree stays balanced instead of making one huge leaf.
    const uint32_t split = begin + count / 2;
    build_node(boxes, centers, begin, split, depth + 1);
    nodes_[index].first = build_node(boxes, centers, split, end, depth + 1);
    nodes_[index].count = 0;
    return index;
  }

  // Bin centroids along the longest axis and sweep for the cheapest split.
  Bin bins[kBins];
  const double scale = kBins / extent;
  auto bin_of = [&](uint32_t prim) {
    return std::min(kBins - 1, static_cast<int>((centers[prim][axis] - lo) * scale));
  };
  for (uint32_t i = begin; i < end; ++i) {
    Bin& b = bins[bin_of(prim_order_[i])];
    b.box.grow(boxes[prim_order_[i]]);
    ++b.count;
  }
  double right_area[kBins];
  uint32_t right_count[kBins];
  Aabb acc;
  uint32_t n = 0;
  for (int i = kBins - 1; i > 0; --i) {
    acc.grow(bins[i].box);
    n += bins[i].count;
    right_area[i] = acc.half_area();
    right_count[i] = n;
  }
  double best_cost = kInf;
  int best_split = -1;
  acc = Aabb{};
  n = 0;
  for (int i = 1; i < kBins; ++i) {
    acc.grow(bins[i - 1].box);
    n += bins[i - 1].count;
    if (n == 0 || right_count[i] == 0) continue;
    const double cost = acc.half_area() * n + right_area[i] * right_count[i];
    if (cost < best_cost) {
      best_cost = cost;
      best_split = i;
    }
  }
  // SAH: intersecting a primitive costs about as much as a box test.
  const double leaf_cost = box.half_area() * count;
  if (best_split < 0 || (count <= kMaxLeaf && best_cost >= leaf_cost)) return make_leaf();

  uint32_t* mid = std::partition(prim_order_.data() + begin, prim_order_.data() + end,
                                 [&](uint32_t prim) { return bin_of(prim) < best_split; });
  const uint32_t split = static_cast<uint32_t>(mid - prim_order_.data());
  build_node(boxes, centers, begin, split, depth + 1);
  const uint32_t right = build_node(boxes, centers, split, end, depth + 1);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

}  // namespace ppm
