// Binned SAH build of a binary BVH (see bvh_build.h).
#include "geometry/bvh_build.h"

#include "base/fill_vector.h"
#include "base/parallel.h"

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

namespace ppm {
namespace {

constexpr int kBins = 16;
// Nodes with more primitives bin a sample of about this many (split()).
constexpr uint32_t kBinnedSample = 1u << 14;
// Right subtrees this large, near the root, are built on a thread of their own (2 levels: up to 4
// threads).
constexpr uint32_t kParallelPrims = 1u << 16;
constexpr int kParallelDepth = 2;

// A primitive as the build moves it: its box beside its index, so that the binning and the
// partition read boxes in sequence (indices alone sent them to random ones: cache misses once the
// arrays outgrow the caches). In float, rounded outwards (float_bounds.h): 28 bytes instead of 52,
// and the Bvh keeps float boxes anyway, so its nodes' boxes are the same as from the double ones.
struct BuildPrim {
  Vec3f lo, hi;
  uint32_t id;

  static BuildPrim of(const Aabb& b, uint32_t id) {
    const FloatAabb f = FloatAabb::around(b);
    return BuildPrim{f.lo, f.hi, id};
  }
  FloatAabb box() const { return FloatAabb{lo, hi}; }
  // In float: the binning's, and the centroid boxes' (so that every centroid is inside its node's).
  Vec3f center() const { return 0.5f * (lo + hi); }
};
static_assert(sizeof(BuildPrim) == 28, "BuildPrim grew");

// The boxes and centroids of a set of primitives, in float as they are.
struct FloatBox {
  FloatAabb box, centroids;
  void add(const BuildPrim& p) {
    box.grow(p.box());
    const Vec3f c = p.center();
    centroids.grow(FloatAabb{c, c});
  }
};

// A bin of primitives' boxes, in float as they are.
struct FloatBin {
  FloatAabb box;
  uint32_t count = 0;
  void add(const BuildPrim& p) {
    box.grow(p.box());
    ++count;
  }
};

class Builder {
 public:
  Builder(size_t count, const std::function<Aabb(size_t)>& box_of, uint32_t max_leaf, int max_depth, BinaryBvh& out)
      : count_(count), box_of_(box_of), max_leaf_(max_leaf), max_depth_(max_depth), out_(out) {}

  void run() {
    const size_t n = count_;
    refs_.resize(n);  // written below, on every thread: the pages' faults too
    constexpr size_t kBlock = 65536;
    const size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<FloatAabb> block_box(blocks);
    std::vector<Aabb> block_cbox(blocks);
    std::vector<size_t> block_bad(blocks, n);  // each block's first non-finite box
    auto fill = [&](size_t b) {
      for (size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
        const Aabb box = box_of_(i);
        if (!is_finite(box.lo) || !is_finite(box.hi)) {
          block_bad[b] = i;
          return;
        }
        refs_[i] = BuildPrim::of(box, static_cast<uint32_t>(i));
        block_box[b].grow(refs_[i].box());
        block_cbox[b].grow(Vec3(refs_[i].center()));
      }
    };
    if (blocks > 1) {
      parallel_each(hardware_threads(), blocks, fill);
    } else if (blocks == 1) {
      fill(0);  // small trees (a dynamic scene's objects, one by one) start no thread
    }
    FloatAabb box;
    Aabb cbox;
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
    parallel_for(hardware_threads(), n, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) out_.order[i] = refs_[i].id;
    });
  }

 private:
  struct Split {
    uint32_t at;
    FloatAabb left_box, right_box;
    Aabb left_cbox, right_cbox;
  };

  // Builds the subtree over order[begin, end) whose box and centroid box are given, appending its
  // nodes depth-first to `nodes` (whose indices it uses); returns the index of its root.
  uint32_t node(std::vector<BinaryBvhNode>& nodes, uint32_t begin, uint32_t end, const FloatAabb& box, const Aabb& cbox,
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

  // Partitions refs[begin, end) at the binned SAH split and returns the halves' boxes. A large node
  // bins a sample of its primitives (every stride-th: about kBinnedSample of them), which picks
  // nearly the same split for a fraction of the memory traffic; the halves' boxes come from the
  // partition's own pass over all of them, so they are exact either way.
  Split split(uint32_t begin, uint32_t end, const Aabb& cbox) {
    BuildPrim* prims = refs_.data();
    const uint32_t stride = std::max(1u, (end - begin) / kBinnedSample);
    const Vec3f origin(cbox.lo);
    Vec3f scale(0.0f);
    for (int a = 0; a < 3; ++a) {
      const float extent = static_cast<float>(cbox.hi[a] - cbox.lo[a]);
      scale[a] = extent > 0.0f ? kBins * (1.0f - 1e-6f) / extent : 0.0f;
    }
    FloatBin bins[3][kBins];
    for (uint32_t i = begin; i < end; i += stride) {
      const BuildPrim& p = prims[i];
      const glm::ivec3 bin = bin_of(p.center(), origin, scale);
      for (int a = 0; a < 3; ++a) bins[a][bin[a]].add(p);
    }
    const auto [best_axis, best] = cheapest_split(bins, scale);
    Split s;
    if (best_axis >= 0) {
      s.at = partition(begin, end, [&](const BuildPrim& p) { return bin_of(p.center(), origin, scale)[best_axis] < best; },
                       s);
      return s;
    }
    // When all centroids coincide (or the bins could not separate them) the split stays at the
    // middle by index, so the tree stays balanced instead of making one huge leaf.
    const uint32_t middle = begin + (end - begin) / 2;
    s.at = partition(begin, end, [&](const BuildPrim& p) { return &p < prims + middle; }, s);
    return s;
  }

  // The (axis, bin) of the lowest surface area heuristic cost: the left half takes the bins below
  // it. (-1, -1) if no axis separates the centroids.
  static std::pair<int, int> cheapest_split(const FloatBin (&bins)[3][kBins], const Vec3f& scale) {
    double best_cost = kInf;
    int best_axis = -1, best = -1;
    for (int a = 0; a < 3; ++a) {
      if (scale[a] == 0.0f) continue;
      double right_area[kBins];
      uint32_t right_count[kBins];
      Aabb acc;
      uint32_t n = 0;
      for (int i = kBins - 1; i > 0; --i) {
        acc.grow(bins[a][i].box.to_double());
        n += bins[a][i].count;
        right_area[i] = acc.half_area();
        right_count[i] = n;
      }
      acc = Aabb{};
      n = 0;
      for (int i = 1; i < kBins; ++i) {
        acc.grow(bins[a][i - 1].box.to_double());
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
    return {best_axis, best};
  }

  // Moves the primitives of [begin, end) that go left before those that do not (Hoare's
  // partition), growing each half's box and centroid box as it passes them; returns the first of
  // the right half. The middle-by-index fallback's test reads the primitive's address: it holds
  // because nothing moves when the halves are already in place.
  template <class GoesLeft>
  uint32_t partition(uint32_t begin, uint32_t end, GoesLeft&& goes_left, Split& s) {
    BuildPrim* prims = refs_.data();
    BuildPrim *lo = prims + begin, *hi = prims + end;
    FloatBox left, right;
    for (;;) {
      while (lo < hi && goes_left(*lo)) left.add(*lo++);
      while (lo < hi && !goes_left(hi[-1])) right.add(*--hi);
      if (lo >= hi) break;
      std::swap(*lo, hi[-1]);
    }
    s.left_box = left.box;
    s.left_cbox = left.centroids.to_double();
    s.right_box = right.box;
    s.right_cbox = right.centroids.to_double();
    return static_cast<uint32_t>(lo - prims);
  }

  // A centroid's bin on each axis, clamped into the bins (rounding may put one a hair outside).
  static glm::ivec3 bin_of(const Vec3f& center, const Vec3f& origin, const Vec3f& scale) {
    const glm::ivec3 bin((center - origin) * scale);
    return glm::clamp(bin, glm::ivec3(0), glm::ivec3(kBins - 1));
  }

  const size_t count_;
  const std::function<Aabb(size_t)>& box_of_;
  const uint32_t max_leaf_;
  const int max_depth_;
  BinaryBvh& out_;
  FillVector<BuildPrim> refs_;
};

}  // namespace

BinaryBvh build_binary_bvh(size_t count, const std::function<Aabb(size_t)>& box_of, uint32_t max_leaf,
                           int max_depth) {
  BinaryBvh out;
  if (count == 0) return out;
  if (max_depth < 0 || max_depth > kMaxBuildDepth) throw std::invalid_argument("BVH: depth limit out of range");
  Builder(count, box_of, std::max(1u, max_leaf), max_depth, out).run();
  return out;
}

BinaryBvh build_binary_bvh(const std::vector<Aabb>& boxes, uint32_t max_leaf, int max_depth) {
  return build_binary_bvh(boxes.size(), [&](size_t i) { return boxes[i]; }, max_leaf, max_depth);
}

}  // namespace ppm
