// Build of the hashed uniform grid: bounds and cell dimensions, then a counting
// sort of (item, cell) references into hash buckets.
#include "ppm/hash_grid.h"
#include "ppm/grid_input.h"

#include "math/aabb.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ppm {
namespace {

constexpr uint64_t kMaxIndex = kMaxGridIndex;
constexpr double kMaxCellsPerAxis = double((1u << 21) - 1);  // 21-bit key fields

void check_input(const std::vector<Vec3>& centers, const std::vector<double>& radii,
                 double cell_size) {
  const std::string who = "HashGrid::build: ";
  if (!(cell_size > 0.0 && cell_size < kInf))
    throw std::invalid_argument(who + "cell_size must be finite and > 0");
  check_grid_items(who, centers, radii);
}

// Half-extent of an item's box: the radius widened by a few ulps so a point
// the caller's rounded distance test accepts is never outside it.
// (|x|+|y|+|z| bounds max_abs without the libm fmax calls GCC emits for it.)
double box_pad(const Vec3& c, double r) {
  return r + 4.0 * DBL_EPSILON * (std::fabs(c.x) + std::fabs(c.y) + std::fabs(c.z) + r);
}

}  // namespace

void HashGrid::build(const std::vector<Vec3>& centers, const std::vector<double>& radii,
                     double cell_size) {
  check_input(centers, radii, cell_size);
  const size_t n = centers.size();
  Aabb bounds;
  for (size_t i = 0; i < n; ++i) {
    const double pad = radii.empty() ? 0.0 : box_pad(centers[i], radii[i]);
    bounds.grow(centers[i] - pad);
    bounds.grow(centers[i] + pad);
  }
  const Vec3 extent = bounds.extent();
  if (n > 0 && !is_finite(extent))
    throw std::invalid_argument("HashGrid::build: the items' extent overflows a double");
  *this = HashGrid();
  if (n == 0) return;
  cell_size = std::max(cell_size, max_abs(extent) / (kMaxCellsPerAxis - 1.0));
  item_count_ = n;
  origin_ = bounds.lo;
  cell_size_ = cell_size;
  inv_cell_ = 1.0 / cell_size;
  for (int a = 0; a < 3; ++a)
    limit_[a] = std::min(std::floor(extent[a] * inv_cell_) + 1.0, kMaxCellsPerAxis);
  int bits = 1;
  while ((size_t(1) << bits) < 2 * n) ++bits;
  shift_ = 64 - bits;
  bucket_begin_.assign((size_t(1) << bits) + 1, 0);
  try {
    if (radii.empty()) {
      fill_points(centers);
    } else {
      fill_spheres(centers, radii);
    }
  } catch (...) {  // too many references or out of memory: leave a valid empty grid
    *this = HashGrid();
    throw;
  }
}

uint32_t HashGrid::cell_coord(int axis, double x) const {
  double f = (x - origin_[axis]) * inv_cell_;
  f = f > 0.0 ? f : 0.0;
  f = f < limit_[axis] - 1.0 ? f : limit_[axis] - 1.0;
  return uint32_t(f);
}

// Counting sort of points into buckets: counts go to bucket_begin_[b], an
// inclusive prefix sum turns them into ends, and a backward fill leaves the
// starts behind with items increasing within a bucket.
void HashGrid::fill_points(const std::vector<Vec3>& centers) {
  const size_t n = centers.size();
  auto key_of = [&](const Vec3& p) {
    return pack(cell_coord(0, p.x), cell_coord(1, p.y), cell_coord(2, p.z));
  };
  std::vector<uint32_t> bucket(n);
  for (size_t i = 0; i < n; ++i) {
    bucket[i] = bucket_of(key_of(centers[i]));
    ++bucket_begin_[bucket[i]];
  }
  for (size_t b = 1; b < bucket_begin_.size(); ++b) bucket_begin_[b] += bucket_begin_[b - 1];
  items_.assign(n, 0);
  keys_.assign(n, 0);
  for (size_t i = n; i-- > 0;) {
    const uint32_t r = --bucket_begin_[bucket[i]];
    items_[r] = static_cast<uint32_t>(i);
    keys_[r] = key_of(centers[i]);
  }
  bucket_begin_.back() = static_cast<uint32_t>(n);
}

// Same over (sphere, cell) references; cell ranges are recomputed in the fill
// pass rather than stored.
void HashGrid::fill_spheres(const std::vector<Vec3>& centers, const std::vector<double>& radii) {
  const size_t n = centers.size();
  auto ranges = [&](size_t i, uint32_t r[6]) {
    const double pad = box_pad(centers[i], radii[i]);
    for (int a = 0; a < 3; ++a) {
      r[a] = cell_coord(a, centers[i][a] - pad);
      r[a + 3] = cell_coord(a, centers[i][a] + pad);
    }
  };
  uint64_t total = 0;
  uint32_t r[6];
  for (size_t i = 0; i < n; ++i) {
    ranges(i, r);
    total += uint64_t(r[3] - r[0] + 1) * (r[4] - r[1] + 1) * (r[5] - r[2] + 1);
    if (total > kMaxIndex) throw std::length_error("HashGrid::build: too many references");
    for (uint32_t z = r[2]; z <= r[5]; ++z)
      for (uint32_t y = r[1]; y <= r[4]; ++y)
        for (uint32_t x = r[0]; x <= r[3]; ++x) ++bucket_begin_[bucket_of(pack(x, y, z))];
  }
  for (size_t b = 1; b < bucket_begin_.size(); ++b) bucket_begin_[b] += bucket_begin_[b - 1];
  items_.assign(total, 0);
  keys_.assign(total, 0);
  for (size_t i = n; i-- > 0;) {
    ranges(i, r);
    for (uint32_t z = r[2]; z <= r[5]; ++z)
      for (uint32_t y = r[1]; y <= r[4]; ++y)
        for (uint32_t x = r[0]; x <= r[3]; ++x) {
          const uint64_t key = pack(x, y, z);
          const uint32_t slot = --bucket_begin_[bucket_of(key)];
          items_[slot] = static_cast<uint32_t>(i);
          keys_[slot] = key;
        }
  }
  bucket_begin_.back() = static_cast<uint32_t>(total);
}

size_t HashGrid::memory_bytes() const {
  return sizeof(*this) + bucket_begin_.capacity() * sizeof(uint32_t) +
         keys_.capacity() * sizeof(uint64_t) + items_.capacity() * sizeof(uint32_t);
}

size_t HashGrid::nonempty_cell_count() const {
  size_t count = 0;
  for (size_t b = 0; b + 1 < bucket_begin_.size(); ++b) count += bucket_begin_[b + 1] > bucket_begin_[b];
  return count;
}

}  // namespace ppm
