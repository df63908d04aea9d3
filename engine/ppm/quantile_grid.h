// Quantile grid: a non-uniform 3D grid whose slab boundaries along each axis
// sit at quantiles of the item centres, so each slab holds about the same
// number of items however unevenly the scene is populated. The PPM gather uses
// it over hit points (spheres, queried with photon positions: mode A) or over
// one pass's photons (points, queried with hit-point boxes: mode B). Cell
// contents are stored contiguously (CSR); queries are header-inline templates
// because they run in the renderer's innermost loop.
#pragma once

#include "math/types.h"
#include "base/fill_vector.h"
#include "ppm/grid_input.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ppm {

class QuantileGrid {
 public:
  // Items per cell the slab counts aim at, averaged over all cells (at most 8
  // cells per item are made whatever the target). Scenes are surfaces, so most
  // cells stay empty and the occupied ones hold far more than this: on the
  // Cornell benchmark (bench/grid_bench.cpp) t = 0.25 leaves 9-17 centres per
  // occupied cell, and query time, which dominates a pass, kept falling down to
  // there in both modes, for 4-16 bytes of cell table per item.
  static constexpr double kDefaultTargetItemsPerCell = 0.25;

  // Throws std::invalid_argument unless target_items_per_cell is finite and > 0.
  explicit QuantileGrid(double target_items_per_cell = kDefaultTargetItemsPerCell);

  // centers[i]: item position; radii empty => points (mode B), else one radius
  // per item, radii[i] >= 0 (mode A: a sphere is listed in every cell its box
  // overlaps, and slabs are kept about a mean radius wide or wider so spheres
  // do not multiply across many thin slabs). Replaces any previous contents.
  // Non-finite centres or radii, negative radii and a size mismatch throw
  // std::invalid_argument naming the item (the grid is then unchanged); more
  // than 2^32-1 items or references throw std::length_error. Points are
  // binned on up to `threads` threads.
  void build(const std::vector<Vec3>& centers, const std::vector<double>& radii, int threads = 1);

  // Visits every item whose sphere may contain p (a superset: the caller does
  // the exact distance test). Each item is visited at most once.
  template <class Fn>
  void for_each_candidate_at(const Vec3& p, Fn&& fn) const {
    const uint32_t cell = (slab_index(2, p.z) * dims_[1] + slab_index(1, p.y)) * dims_[0] +
                          slab_index(0, p.x);
    visit(cell_begin_[cell], cell_begin_[cell + 1], fn);
  }

  // Visits every item listed in a cell overlapping [lo, hi]. Points (mode B)
  // are visited at most once; a sphere spanning several of those cells is
  // visited once per cell.
  template <class Fn>
  void for_each_candidate_in_box(const Vec3& lo, const Vec3& hi, Fn&& fn) const {
    for_each_run_in_box(lo, hi, [&](uint32_t begin, uint32_t end) { visit(begin, end, fn); });
  }

  // fn(begin, end) once per row of cells overlapping [lo, hi] (possibly with
  // begin == end): cells along x are adjacent in CSR order, so a row's items
  // are the positions [begin, end) of the cell-ordered item list. After
  // relabel_in_cell_order (points) item k is stored at position k, so these
  // are labels, and a caller loops over its own cell-ordered arrays without
  // an index lookup per item.
  template <class Fn>
  void for_each_run_in_box(const Vec3& lo, const Vec3& hi, Fn&& fn) const {
    const uint32_t x0 = slab_index(0, lo.x), x1 = slab_index(0, hi.x);
    const uint32_t y0 = slab_index(1, lo.y), y1 = slab_index(1, hi.y);
    const uint32_t z0 = slab_index(2, lo.z), z1 = slab_index(2, hi.z);
    for (uint32_t z = z0; z <= z1; ++z) {
      for (uint32_t y = y0; y <= y1; ++y) {
        const uint32_t row = (z * dims_[1] + y) * dims_[0];
        fn(cell_begin_[row + x0], cell_begin_[row + x1 + 1]);
      }
    }
  }

  // Slab along `axis` holding coordinate x: the number of splits <= x, so a
  // value equal to a split belongs to the slab that starts there. Slab 0 and
  // the last slab extend to -inf / +inf; NaN maps to slab 0.
  uint32_t slab_index(int axis, double x) const {
    const SlabLookup& lookup = lookup_[axis];
    if (lookup.first.empty()) return 0;  // no splits
    // A uniform table narrows the search to the splits in x's bucket (a few at
    // most): the binary search over all splits was a fifth of the gather.
    const uint32_t b = lookup.bucket(x);
    const uint32_t begin = lookup.first[b];
    return begin + upper_bound_count(splits_[axis].data() + begin, lookup.first[b + 1] - begin, x);
  }

  size_t item_count() const { return item_count_; }
  size_t cell_count() const { return cell_begin_.size() - 1; }
  size_t reference_count() const { return items_.size(); }

  // Point items only (mode B): relabels the items 0..n-1 in the order the
  // cells store them and leaves in `old_of_new`, for each new label, the old
  // one. A caller that reorders its own data by it reads a cell's items from
  // contiguous memory, which is what the gather's time goes to, and can use
  // for_each_run_in_box.
  void relabel_in_cell_order(std::vector<uint32_t>& old_of_new) { relabel_items_in_order(items_, old_of_new); }
  size_t memory_bytes() const;
  size_t nonempty_cell_count() const;
  double target_items_per_cell() const { return target_; }
  uint32_t slab_count(int axis) const { return dims_[axis]; }
  // Strictly increasing split values of one axis (slab_count(axis) - 1 of them).
  const std::vector<double>& splits(int axis) const { return splits_[axis]; }

 private:
  // Maps a coordinate to a bucket of a uniform partition of the split range;
  // first[b] counts the splits in buckets before b. Splits are bucketed with
  // the same monotone formula as queries, so splits in earlier buckets are
  // below any x in bucket b and splits in later ones above it: only bucket
  // b's own splits need comparing, and the result is exact.
  struct SlabLookup {
    double origin = 0.0, scale = 0.0;
    double limit = 0.0;  // = last, as a double
    uint32_t last = 0;   // index of the last bucket
    std::vector<uint32_t> first;  // buckets + 1 entries; empty when there are no splits
    // Monotone in x; NaN goes to bucket 0.
    uint32_t bucket(double x) const {
      const double f = (x - origin) * scale;
      return f > 0.0 ? (f < limit ? static_cast<uint32_t>(f) : last) : 0u;
    }
  };

  // Number of values in the sorted s[0, len) that are <= x.
  static uint32_t upper_bound_count(const double* s, uint32_t len, double x) {
    if (len == 0) return 0;
    const double* base = s;
    // Branch-free: the loop count depends on len only, and the step is masked
    // rather than selected (GCC turns a ?: here into a mispredicted branch).
    while (len > 1) {
      const uint32_t half = len >> 1;
      base += half & (0u - static_cast<uint32_t>(base[half - 1] <= x));
      len -= half;
    }
    return static_cast<uint32_t>(base - s) + static_cast<uint32_t>(*base <= x);
  }

  void build_lookup(int axis);

  template <class Fn>
  void visit(uint32_t begin, uint32_t end, Fn& fn) const {
    const uint32_t* items = items_.data();
    for (uint32_t i = begin; i < end; ++i) fn(items[i]);
  }

  void choose_splits(const std::vector<Vec3>& centers, double min_width);
  void fill_points(const std::vector<Vec3>& centers, int threads);
  void fill_spheres(const std::vector<Vec3>& centers, const std::vector<double>& radii);

  double target_;
  size_t item_count_ = 0;
  uint32_t dims_[3] = {1, 1, 1};
  std::vector<double> splits_[3];
  SlabLookup lookup_[3];
  FillVector<uint32_t> cell_begin_{0, 0};  // size cells + 1; zeroed by the fill, in parallel for points
  std::vector<uint32_t> items_;
  // Point build scratch, kept across builds: each point's cell, and the points of each part of the fill.
  FillVector<uint32_t> cell_of_;
  std::vector<FillVector<uint32_t>> part_points_;
};

}  // namespace ppm
