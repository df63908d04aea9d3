// Hashed uniform grid: the comparison structure for the quantile grid, with the
// same query interface so the PPM gather can be a template over the index.
// Cells of a fixed size are hashed into a power-of-two table of about 2n
// buckets whose contents are stored contiguously (CSR). Every reference keeps
// the key of its own cell, and queries skip references whose key differs: that
// drops hash collisions and guarantees each point is visited at most once even
// when two cells of a query box share a bucket.
#pragma once

#include "math/types.h"
#include "ppm/grid_input.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ppm {

class HashGrid {
 public:
  // centers / radii as for QuantileGrid::build (radii empty => points, mode B;
  // else spheres, mode A, listed in every cell their box overlaps). cell_size
  // must be finite and > 0; it is enlarged if the bounds would need more than
  // 2^21 - 1 cells along an axis (cell keys pack 21 bits per axis). Replaces
  // any previous contents. Bad input throws std::invalid_argument naming the
  // item (the grid is then unchanged); more than 2^32-1 items or references
  // throw std::length_error.
  void build(const std::vector<Vec3>& centers, const std::vector<double>& radii, double cell_size);

  // Visits every item whose sphere may contain p, each at most once. Points
  // outside the built bounds (and NaN) find nothing.
  template <class Fn>
  void for_each_candidate_at(const Vec3& p, Fn&& fn) const {
    const double fx = (p.x - origin_.x) * inv_cell_;
    const double fy = (p.y - origin_.y) * inv_cell_;
    const double fz = (p.z - origin_.z) * inv_cell_;
    if (!(fx >= 0.0 && fx < limit_[0] && fy >= 0.0 && fy < limit_[1] && fz >= 0.0 &&
          fz < limit_[2]))
      return;
    visit_cell(pack(uint32_t(fx), uint32_t(fy), uint32_t(fz)), fn);
  }

  // Visits every item listed in a cell overlapping [lo, hi]. Points (mode B)
  // are visited at most once; a sphere spanning several of those cells is
  // visited once per cell.
  template <class Fn>
  void for_each_candidate_in_box(const Vec3& lo, const Vec3& hi, Fn&& fn) const {
    if (keys_.empty()) return;  // also keeps cell_range away from a zero-cell grid
    uint32_t c0[3], c1[3];
    for (int a = 0; a < 3; ++a)
      if (!cell_range(a, lo[a], hi[a], c0[a], c1[a])) return;
    const uint64_t box_cells =
        uint64_t(c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1);
    if (box_cells > keys_.size()) {
      // More cells than references: one pass over all references is cheaper.
      visit_all_in_range(c0, c1, fn);
      return;
    }
    for (uint32_t z = c0[2]; z <= c1[2]; ++z)
      for (uint32_t y = c0[1]; y <= c1[1]; ++y)
        for (uint32_t x = c0[0]; x <= c1[0]; ++x) visit_cell(pack(x, y, z), fn);
  }

  // Points relabelled in cell order (relabel_in_cell_order) only: item k is
  // then stored at position k. fn(begin, end) receives the items of the box's
  // cells as runs of labels, as QuantileGrid::for_each_run_in_box does; here
  // every run is one item, since a bucket mixes the cells that hash to it.
  template <class Fn>
  void for_each_run_in_box(const Vec3& lo, const Vec3& hi, Fn&& fn) const {
    for_each_candidate_in_box(lo, hi, [&](uint32_t item) { fn(item, item + 1); });
  }

  size_t item_count() const { return item_count_; }
  size_t cell_count() const { return bucket_begin_.size() - 1; }  // hash buckets
  size_t reference_count() const { return items_.size(); }

  // Point items only (mode B): relabels the items 0..n-1 in the order the
  // cells store them and leaves in `old_of_new`, for each new label, the old
  // one. A caller that reorders its own data by it reads a cell's items from
  // contiguous memory, which is what the gather's time goes to, and can use
  // for_each_run_in_box.
  void relabel_in_cell_order(std::vector<uint32_t>& old_of_new) { relabel_items_in_order(items_, old_of_new); }
  size_t memory_bytes() const;
  size_t nonempty_cell_count() const;  // non-empty buckets
  double cell_size() const { return cell_size_; }  // as used, after any enlargement

 private:
  static uint64_t pack(uint32_t x, uint32_t y, uint32_t z) {
    return uint64_t(x) | (uint64_t(y) << 21) | (uint64_t(z) << 42);
  }
  uint32_t bucket_of(uint64_t key) const {
    return static_cast<uint32_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);  // Fibonacci hashing
  }

  template <class Fn>
  void visit_cell(uint64_t key, Fn& fn) const {
    const uint32_t b = bucket_of(key);
    const uint64_t* keys = keys_.data();
    const uint32_t* items = items_.data();
    for (uint32_t r = bucket_begin_[b], end = bucket_begin_[b + 1]; r < end; ++r)
      if (keys[r] == key) fn(items[r]);
  }

  template <class Fn>
  void visit_all_in_range(const uint32_t c0[3], const uint32_t c1[3], Fn& fn) const {
    constexpr uint64_t kMask = (uint64_t(1) << 21) - 1;
    for (size_t r = 0; r < keys_.size(); ++r) {
      const uint64_t k = keys_[r];
      const uint32_t x = uint32_t(k & kMask), y = uint32_t((k >> 21) & kMask), z = uint32_t(k >> 42);
      if (x >= c0[0] && x <= c1[0] && y >= c0[1] && y <= c1[1] && z >= c0[2] && z <= c1[2])
        fn(items_[r]);
    }
  }

  // Range of cells along `axis` that [lo, hi] overlaps, clipped to the grid;
  // false if none (inverted box, outside, NaN).
  bool cell_range(int axis, double lo, double hi, uint32_t& c0, uint32_t& c1) const {
    double f0 = (lo - origin_[axis]) * inv_cell_;
    double f1 = (hi - origin_[axis]) * inv_cell_;
    if (!(f1 >= 0.0 && f0 < limit_[axis])) return false;
    f0 = f0 > 0.0 ? f0 : 0.0;
    f1 = f1 < limit_[axis] - 1.0 ? f1 : limit_[axis] - 1.0;
    c0 = uint32_t(f0);
    c1 = uint32_t(f1);
    return c0 <= c1;
  }
  uint32_t cell_coord(int axis, double x) const;

  void fill_points(const std::vector<Vec3>& centers);
  void fill_spheres(const std::vector<Vec3>& centers, const std::vector<double>& radii);

  size_t item_count_ = 0;
  Vec3 origin_{0.0};
  double cell_size_ = 1.0;
  double inv_cell_ = 1.0;
  double limit_[3] = {0.0, 0.0, 0.0};  // cells per axis, as doubles for the range tests
  int shift_ = 63;                     // 64 - log2(bucket count)
  std::vector<uint32_t> bucket_begin_{0, 0, 0};  // size buckets + 1
  std::vector<uint64_t> keys_;                   // cell key of each reference
  std::vector<uint32_t> items_;
};

}  // namespace ppm
