// Binned SAH build of a binary BVH (see bvh_build.h).
#include "geometry/bvh_build.h"

#include "ppm/fill_vector.h"
#include "ppm/parallel.h"

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>

namespace ppm {
namespace {

constexpr int kBins = 16;
// Right subtrees this large, near the root, are built on a thread of their own (2 levels: up to 4
// threads).
constexpr uint32_t kParallelPrims = 1u << 16;
constexpr int kParallelDepth = 2;

// Asked once: hardware_concurrency reads /sys on Linux, 10 us a call, and a dynamic scene builds
// thousands of small trees.
int build_threads() {
  static const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return threads;
}

struct Bin {
  Aabb box, cbox;  // of the primitives' boxes, and of their centroids
  uint32_t count = 0;
};

// A primitive as the build moves it: its centroid beside its index, so that the binning and the
// partition read centroids in sequence (indices alone sent them to random ones: cache misses once
// the arrays outgrow the caches). The box stays in the input, read once per level.
struct BuildPrim {
  Vec3 center;
  uint32_t id;
};

class Builder {
 public:
  Builder(const std::vector<Aabb>& boxes, uint32_t max_leaf, int max_depth, BinaryBvh& out)
      : boxes_(boxes), max_leaf_(max_leaf), max_depth_(max_depth), out_(out) {}

  void run() {
    const size_t n = boxes_.size();
    refs_.resize(n);  // written below, on every thread: the pages' faults too
    constexpr size_t kBlock = 65536;
    const size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<Aabb> block_box(blocks), block_cbox(blocks);
    std::vector<size_t> block_bad(blocks, n);  // each block's first non-finite box
    auto fill = [&](size_t b) {
      for (size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
        const Aabb& box = boxes_[i];
        if (!is_finite(box.lo) || !is_finite(box.hi)) {
          block_bad[b] = i;
          return;
        }
        refs_[i] = BuildPrim{box.center(), static_cast<uint32_t>(i)};
        block_box[b].grow(box);
        block_cbox[b].grow(box.center());
      }
    };
    if (blocks > 1) {
      parallel_each(build_threads(), blocks, fill);
    } else if (blocks == 1) {
      fill(0);  // small trees (a dynamic scene's objects, one by one) start no thread
    }
    Aabb box, cbox;
    for (size_t b = 0; b < blocks; ++b) {
      if (block_bad[b] < n)
        throw std::invalid_argument("BVH: primitive " + std::to_string(block_bad[b]) +
                                    " has a non-finite bounding box");
      box.grow(block_box[b]);
      cbox.grow(block_cbox[b]);
    }
    out_.nodes.reserve(2 * n / std::max(1u, max_leaf_ / 2) + 2);
    node(out_.nodes, 0, static_cast<uint32_t>(n), box, cbox, 0);
    out_.order.resize(n);
    parallel_for(build_threads(), n, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) out_.order[i] = refs_[i].id;
    });
  }

 private:
  struct Split {
    uint32_t at;
    Aabb left_box, left_cbox, right_box, right_cbox;
  };

  // Builds the subtree over order[begin, end) whose box and centroid box are given, appending its
  // nodes depth-first to `nodes` (whose indices it uses); returns the index of its root.
  uint32_t node(std::vector<BinaryBvhNode>& nodes, uint32_t begin, uint32_t end, const Aabb& box, const Aabb& cbox,
                int depth) {
    const uint32_t index = static_cast<uint32_t>(nodes.size());
    nodes.push_back(BinaryBvhNode{box, begin, end - begin});
    const uint32_t count = end - begin;
    if (count <= max_leaf_ || depth >= max_depth_) return index;
    const Split s = split(begin, end, cbox);
    nodes[index].count = 0;
    if (count >= kParallelPrims && depth < kParallelDepth) {
      // The right half on another thread into a list of its own, the left here straight after this
      // node; then the right after the left: the depth-first layout one thread makes, with one copy
      // of the right half's nodes (reserved whole, so that the worker never regrows it).
      std::vector<BinaryBvhNode> right;
      right.reserve(2 * static_cast<size_t>(end - s.at));
      std::exception_ptr failed;
      std::thread worker([&] {
        try {
          node(right, s.at, end, s.right_box, s.right_cbox, depth + 1);
        } catch (...) {
          failed = std::current_exception();
        }
      });
      try {
        node(nodes, begin, s.at, s.left_box, s.left_cbox, depth + 1);
      } catch (...) {
        worker.join();
        throw;
      }
      worker.join();
      if (failed) std::rethrow_exception(failed);
      nodes[index].first = static_cast<uint32_t>(nodes.size());
      append(nodes, right);
      return index;
    }
    node(nodes, begin, s.at, s.left_box, s.left_cbox, depth + 1);
    const uint32_t right = node(nodes, s.at, end, s.right_box, s.right_cbox, depth + 1);
    nodes[index].first = right;
    return index;
  }

  // A subtree built with indices from 0, moved to the end of `nodes`.
  static void append(std::vector<BinaryBvhNode>& nodes, const std::vector<BinaryBvhNode>& subtree) {
    const uint32_t offset = static_cast<uint32_t>(nodes.size());
    for (BinaryBvhNode n : subtree) {
      if (!n.is_leaf()) n.first += offset;  // a leaf's first indexes the shared order
      nodes.push_back(n);
    }
  }

  // Partitions refs[begin, end) at the binned SAH split and returns the halves' boxes.
  Split split(uint32_t begin, uint32_t end, const Aabb& cbox) {
    BuildPrim* prims = refs_.data();
    const uint32_t count = end - begin;
    // Bin centroids along all three axes in one pass; sweep each axis for the
    // split with the lowest surface area heuristic cost.
    Bin bins[3][kBins];
    double scale[3];
    for (int a = 0; a < 3; ++a) {
      const double extent = cbox.hi[a] - cbox.lo[a];
      scale[a] = extent > 0.0 ? kBins * (1.0 - 1e-9) / extent : 0.0;
    }
    auto bin_of = [&](const Vec3& center, int a) {
      return std::min(kBins - 1, static_cast<int>((center[a] - cbox.lo[a]) * scale[a]));
    };
    for (uint32_t i = begin; i < end; ++i) {
      const Aabb& box = boxes_[prims[i].id];
      const Vec3& center = prims[i].center;
      for (int a = 0; a < 3; ++a) {
        Bin& b = bins[a][bin_of(center, a)];
        b.box.grow(box);
        b.cbox.grow(center);
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
    Split s;
    if (best_axis >= 0) {
      s.at = static_cast<uint32_t>(
          std::partition(prims + begin, prims + end,
                         [&](const BuildPrim& p) { return bin_of(p.center, best_axis) < best; }) -
          prims);
      // The halves' boxes are their bins' (no second pass over the primitives).
      for (int i = 0; i < kBins; ++i) {
        const Bin& b = bins[best_axis][i];
        (i < best ? s.left_box : s.right_box).grow(b.box);
        (i < best ? s.left_cbox : s.right_cbox).grow(b.cbox);
      }
      return s;
    }
    // When all centroids coincide (or the bins could not separate them) the
    // split stays at the middle by index, so the tree stays balanced instead
    // of making one huge leaf.
    s.at = begin + count / 2;
    for (uint32_t i = begin; i < s.at; ++i) {
      s.left_box.grow(boxes_[prims[i].id]);
      s.left_cbox.grow(prims[i].center);
    }
    for (uint32_t i = s.at; i < end; ++i) {
      s.right_box.grow(boxes_[prims[i].id]);
      s.right_cbox.grow(prims[i].center);
    }
    return s;
  }

  const std::vector<Aabb>& boxes_;
  const uint32_t max_leaf_;
  const int max_depth_;
  BinaryBvh& out_;
  FillVector<BuildPrim> refs_;
};

}  // namespace

BinaryBvh build_binary_bvh(const std::vector<Aabb>& boxes, uint32_t max_leaf, int max_depth) {
  BinaryBvh out;
  if (boxes.empty()) return out;
  if (max_depth < 0 || max_depth > kMaxBuildDepth) throw std::invalid_argument("BVH: depth limit out of range");
  Builder(boxes, std::max(1u, max_leaf), max_depth, out).run();
  return out;
}

}  // namespace ppm
