// Binned SAH build of a binary BVH (see bvh_build.h).
#include "geometry/bvh_build.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace ppm {
namespace {

constexpr int kBins = 16;
constexpr int kMaxDepth = 60;  // keeps traversal stacks small and bounded

struct Bin {
  Aabb box;
  uint32_t count = 0;
};

class Builder {
 public:
  Builder(const std::vector<Aabb>& boxes, uint32_t max_leaf, BinaryBvh& out)
      : boxes_(boxes), max_leaf_(max_leaf), out_(out), centers_(boxes.size()) {}

  void run() {
    Aabb box, cbox;
    for (size_t i = 0; i < boxes_.size(); ++i) {
      if (!is_finite(boxes_[i].lo) || !is_finite(boxes_[i].hi))
        throw std::invalid_argument("BVH: primitive " + std::to_string(i) + " has a non-finite bounding box");
      centers_[i] = boxes_[i].center();
      box.grow(boxes_[i]);
      cbox.grow(centers_[i]);
    }
    out_.order.resize(boxes_.size());
    std::iota(out_.order.begin(), out_.order.end(), 0u);
    out_.nodes.reserve(2 * boxes_.size() / std::max(1u, max_leaf_ / 2) + 2);
    node(0, static_cast<uint32_t>(boxes_.size()), box, cbox, 0);
  }

 private:
  // Builds the subtree over order[begin, end) whose box and centroid box are given.
  uint32_t node(uint32_t begin, uint32_t end, const Aabb& box, const Aabb& cbox, int depth) {
    const uint32_t index = static_cast<uint32_t>(out_.nodes.size());
    out_.nodes.push_back(BinaryBvhNode{box, begin, end - begin});
    const uint32_t count = end - begin;
    if (count <= max_leaf_ || depth >= kMaxDepth) return index;

    uint32_t* prims = out_.order.data();
    uint32_t split = begin + count / 2;
    // Bin centroids along all three axes in one pass; sweep each axis for the
    // split with the lowest surface area heuristic cost.
    Bin bins[3][kBins];
    double scale[3];
    for (int a = 0; a < 3; ++a) {
      const double extent = cbox.hi[a] - cbox.lo[a];
      scale[a] = extent > 0.0 ? kBins * (1.0 - 1e-9) / extent : 0.0;
    }
    auto bin_of = [&](uint32_t prim, int a) {
      return std::min(kBins - 1, static_cast<int>((centers_[prim][a] - cbox.lo[a]) * scale[a]));
    };
    for (uint32_t i = begin; i < end; ++i) {
      const uint32_t p = prims[i];
      for (int a = 0; a < 3; ++a) {
        Bin& b = bins[a][bin_of(p, a)];
        b.box.grow(boxes_[p]);
        ++b.count;
      }
    }
    double best_cost = kInf;
    int best_axis = -1, best = -1;
    for (int a = 0; a < 3; ++a) {
      if (scale[a] == 0.0) continue;
      double right_area[kBins];
      uint32_t right_count[kBins];
      Aabb acc;
      uint32_t n = 0;
      for (int i = kBins - 1; i > 0; --i) {
        acc.grow(bins[a][i].box);
        n += bins[a][i].count;
        right_area[i] = acc.half_area();
        right_count[i] = n;
      }
      acc = Aabb{};
      n = 0;
      for (int i = 1; i < kBins; ++i) {
        acc.grow(bins[a][i - 1].box);
        n += bins[a][i - 1].count;
        if (n == 0 || right_count[i] == 0) continue;
        const double cost = acc.half_area() * n + right_area[i] * right_count[i];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = a;
          best = i;
        }
      }
    }
    if (best_axis >= 0) {
      split = static_cast<uint32_t>(
          std::partition(prims + begin, prims + end, [&](uint32_t p) { return bin_of(p, best_axis) < best; }) - prims);
    }
    // When all centroids coincide (or the bins could not separate them) the
    // split stays at the middle by index, so the tree stays balanced instead
    // of making one huge leaf.
    Aabb left_box, right_box, left_cbox, right_cbox;
    for (uint32_t i = begin; i < split; ++i) {
      left_box.grow(boxes_[prims[i]]);
      left_cbox.grow(centers_[prims[i]]);
    }
    for (uint32_t i = split; i < end; ++i) {
      right_box.grow(boxes_[prims[i]]);
      right_cbox.grow(centers_[prims[i]]);
    }
    out_.nodes[index].count = 0;
    node(begin, split, left_box, left_cbox, depth + 1);
    const uint32_t right = node(split, end, right_box, right_cbox, depth + 1);
    out_.nodes[index].first = right;
    return index;
  }

  const std::vector<Aabb>& boxes_;
  const uint32_t max_leaf_;
  BinaryBvh& out_;
  std::vector<Vec3> centers_;
};

}  // namespace

BinaryBvh build_binary_bvh(const std::vector<Aabb>& boxes, uint32_t max_leaf) {
  BinaryBvh out;
  if (boxes.empty()) return out;
  Builder(boxes, std::max(1u, max_leaf), out).run();
  return out;
}

}  // namespace ppm
