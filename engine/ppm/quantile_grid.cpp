// Build of the quantile grid: per-axis splits by multi-selection (nth_element
// recursion) over a sample of the coordinates, then a counting sort of items
// (or of sphere references) into CSR cells. O(n) overall.
#include "ppm/quantile_grid.h"
#include "ppm/grid_input.h"
#include "base/parallel.h"

#include "math/rng.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ppm {
namespace {

constexpr uint64_t kMaxIndex = kMaxGridIndex;
// Cells never outnumber items by more than this, so memory stays O(n) even for
// tiny targets.
constexpr double kMaxCellsPerItem = 8.0;
constexpr double kMaxCells = 2147483648.0;  // keeps cell indices in uint32
constexpr uint32_t kSamplesPerSlab = 128;
constexpr double kMinSlabWidthInRadii = 1.0;

// Places the order statistics at positions pos[0..npos) (increasing) of
// data[first, last) where a full sort would put them.
void select_positions(double* data, size_t first, size_t last, const size_t* pos, size_t npos) {
  if (npos == 0 || last - first < 2) return;
  const size_t mid = npos / 2;
  const size_t k = pos[mid];
  std::nth_element(data + first, data + k, data + last);
  select_positions(data, first, k, pos, mid);
  select_positions(data, k + 1, last, pos + mid + 1, npos - mid - 1);
}

struct Split {
  double value;
  bool wall;  // several quantiles landed on this value: a wall or a pile of duplicates
};

// A wall taken as a split would lie exactly on a slab boundary, and the first
// quantile past a wall's run often cuts a sliver slab right next to it; either
// way spheres on the wall and query boxes around it straddle two slabs. So:
// (1) drop an ordinary split closer to an adjacent wall than half the width of
// its slab on the other side; (2) move each wall split half-way down towards
// the split below, so the wall lies inside a slab with a margin on both sides.
// Both steps keep the sequence strictly increasing.
std::vector<double> place_splits_around_walls(const std::vector<Split>& raw, double min_value,
                                              bool min_wall, double max_value) {
  std::vector<Split> kept;
  kept.reserve(raw.size());
  const size_t n = raw.size();
  for (size_t j = 0; j < n; ++j) {
    const double v = raw[j].value;
    const double below = j > 0 ? raw[j - 1].value : min_value;
    const double above = j + 1 < n ? raw[j + 1].value : max_value;
    const bool wall_below = j > 0 ? raw[j - 1].wall : min_wall;
    const bool wall_above = j + 1 < n && raw[j + 1].wall;
    const bool sliver = (wall_below && v - below < 0.5 * (above - v)) ||
                        (wall_above && above - v < 0.5 * (v - below));
    if (raw[j].wall || !sliver) kept.push_back(raw[j]);
  }
  std::vector<double> splits(kept.size());
  for (size_t j = kept.size(); j-- > 0;) {  // downwards: kept[j - 1] is still unmoved
    splits[j] = kept[j].value;
    if (!kept[j].wall) continue;
    const double below = j > 0 ? kept[j - 1].value : min_value;
    const double mid = below + 0.5 * (kept[j].value - below);
    if (mid > below) splits[j] = mid;
  }
  return splits;
}

// Coordinates the quantiles are taken from: all of them for small inputs,
// else a fixed pseudo-random sample of kSamplesPerSlab per slab. Slabs then
// hold equal counts to within ~10% (+1% candidates per query on the Cornell
// benchmark), while exact selection over 1M photons took two thirds of a
// mode-B build. Hashed indices, not a stride, so that input order (wall by
// wall, say) cannot bias the sample.
size_t sample_coordinates(const std::vector<Vec3>& centers, int axis, uint32_t slabs,
                          std::vector<double>& scratch) {
  const size_t n = centers.size();
  const size_t m = std::min<size_t>(n, size_t(kSamplesPerSlab) * slabs);
  scratch.resize(m);
  if (m == n) {
    for (size_t i = 0; i < n; ++i) scratch[i] = centers[i][axis];
  } else {
    for (size_t j = 0; j < m; ++j) scratch[j] = centers[mix64(j * 3 + axis) % n][axis];
  }
  return m;
}

// Drops splits closer than min_width to the previous one kept: a safety net
// behind the slab caps for dense spots, where quantile slabs get narrow. Spheres
// are listed in every slab they overlap, so they multiply when slabs get much
// narrower than they are (50k spheres on one plane: 44 references each).
std::vector<double> thin_splits(std::vector<double> splits, double min_width) {
  if (!(min_width > 0.0)) return splits;
  size_t kept = 0;
  for (size_t j = 0; j < splits.size(); ++j)
    if (kept == 0 || splits[j] - splits[kept - 1] >= min_width) splits[kept++] = splits[j];
  splits.resize(kept);
  return splits;
}

// Splits of one axis aiming at `slabs` equally filled slabs. Repeated quantile
// values (planar walls, duplicates) collapse to one split, and a split equal to
// the minimum would only open an empty first slab, so both are dropped; walls
// are then kept off slab boundaries. The result is strictly increasing and may
// be shorter than slabs - 1.
std::vector<double> axis_splits(const std::vector<Vec3>& centers, int axis, uint32_t slabs,
                                double min_width, std::vector<double>& scratch) {
  const size_t n = centers.size();
  if (slabs <= 1 || n == 0) return {};
  const size_t m = sample_coordinates(centers, axis, slabs, scratch);
  const double min_value = *std::min_element(scratch.begin(), scratch.end());
  const double max_value = *std::max_element(scratch.begin(), scratch.end());
  std::vector<size_t> pos(slabs - 1);
  for (uint32_t k = 1; k < slabs; ++k) pos[k - 1] = static_cast<size_t>(uint64_t(k) * m / slabs);
  select_positions(scratch.data(), 0, m, pos.data(), pos.size());
  std::vector<Split> raw;
  raw.reserve(pos.size());
  bool min_wall = false;
  for (size_t p : pos) {
    const double v = scratch[p];
    if (v <= min_value) {
      min_wall = true;
    } else if (!raw.empty() && v == raw.back().value) {
      raw.back().wall = true;
    } else {
      raw.push_back({v, false});
    }
  }
  return thin_splits(place_splits_around_walls(raw, min_value, min_wall, max_value), min_width);
}

// Narrowest slab worth making for spheres (0 for points): a multiple of the
// mean radius.
double min_slab_width(const std::vector<double>& radii) {
  if (radii.empty()) return 0.0;
  double sum = 0.0;
  for (double r : radii) sum += r;
  return kMinSlabWidthInRadii * sum / static_cast<double>(radii.size());
}

// Most slabs worth making along each axis: as many as items, and for spheres
// no more than fit at min_width across the centres' extent.
void slab_caps(const std::vector<Vec3>& centers, double min_width, double cap[3]) {
  const double n = std::max(1.0, static_cast<double>(centers.size()));
  cap[0] = cap[1] = cap[2] = n;
  if (!(min_width > 0.0) || centers.empty()) return;
  Vec3 lo = centers[0], hi = centers[0];
  for (const Vec3& c : centers) {
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  for (int a = 0; a < 3; ++a) cap[a] = std::clamp(std::floor((hi[a] - lo[a]) / min_width), 1.0, n);
}

// Sphere box, widened by a few ulps so a point the caller's rounded distance
// test accepts is never outside it.
void sphere_box(const Vec3& c, double r, Vec3& lo, Vec3& hi) {
  // |x|+|y|+|z| bounds max_abs without the libm fmax calls GCC emits for it.
  const double pad = r + 4.0 * DBL_EPSILON * (std::fabs(c.x) + std::fabs(c.y) + std::fabs(c.z) + r);
  lo = c - pad;
  hi = c + pad;
}

}  // namespace

QuantileGrid::QuantileGrid(double target_items_per_cell) : target_(target_items_per_cell) {
  if (!(target_items_per_cell > 0.0 && target_items_per_cell < kInf))
    throw std::invalid_argument("QuantileGrid: target_items_per_cell must be finite and > 0");
}

void QuantileGrid::build(const std::vector<Vec3>& centers, const std::vector<double>& radii, int threads) {
  check_grid_items("QuantileGrid::build: ", centers, radii);
  try {
    item_count_ = centers.size();
    choose_splits(centers, min_slab_width(radii));
    if (radii.empty()) {
      fill_points(centers, threads);
    } else {
      fill_spheres(centers, radii);
    }
  } catch (...) {  // too many references or out of memory: leave a valid empty grid
    *this = QuantileGrid(target_);
    throw;
  }
}

// Slab counts: the cell budget n / target is shared evenly (cube root) between
// the axes; an axis that cannot reach its share, because its coordinates repeat
// (a wall, a line, duplicates) or because spheres cap it, keeps what it got and
// the others split the rest, so a planar point set still gets ~target items
// per cell instead of n^(1/3).
void QuantileGrid::choose_splits(const std::vector<Vec3>& centers, double min_width) {
  const double n = static_cast<double>(centers.size());
  const double budget = std::max(1.0, std::min({n / target_, kMaxCellsPerItem * n, kMaxCells}));
  double cap[3];
  slab_caps(centers, min_width, cap);
  std::vector<double> scratch;
  uint32_t requested[3] = {0, 0, 0};
  bool fixed[3] = {false, false, false};
  for (int a = 0; a < 3; ++a) {
    splits_[a].clear();
    dims_[a] = 1;
  }
  for (int round = 0; round < 3; ++round) {
    double fixed_product = 1.0;
    int free_axes = 0;
    for (int a = 0; a < 3; ++a) {
      if (fixed[a]) fixed_product *= dims_[a];
      else ++free_axes;
    }
    if (free_axes == 0) break;
    const double share = std::round(std::pow(budget / fixed_product, 1.0 / free_axes));
    bool short_axis = false;
    for (int a = 0; a < 3; ++a) {
      const uint32_t want = static_cast<uint32_t>(std::clamp(share, 1.0, cap[a]));
      if (fixed[a] || requested[a] == want) continue;
      requested[a] = want;
      splits_[a] = axis_splits(centers, a, want, 0.5 * min_width, scratch);
      dims_[a] = static_cast<uint32_t>(splits_[a].size() + 1);
      if (dims_[a] < share) fixed[a] = short_axis = true;
    }
    if (!short_axis) break;
  }
  for (int a = 0; a < 3; ++a) build_lookup(a);
  const size_t cells = size_t(dims_[0]) * dims_[1] * dims_[2];
  cell_begin_.resize(cells + 1);  // zeroed by the fill
}

void QuantileGrid::build_lookup(int axis) {
  const std::vector<double>& s = splits_[axis];
  SlabLookup& lookup = lookup_[axis];
  lookup = SlabLookup{};
  if (s.empty()) return;
  // Four buckets per slab: most buckets then hold no split or one.
  const uint32_t buckets = static_cast<uint32_t>(std::min<size_t>(4 * (s.size() + 1), kMaxIndex / 2));
  lookup.origin = s.front();
  const double span = s.back() - s.front();
  // A zero or overflowing span leaves scale 0 (one bucket in effect): still exact, just a full search.
  lookup.scale = span > 0.0 && std::isfinite(span) && std::isfinite(buckets / span) ? buckets / span : 0.0;
  lookup.last = buckets - 1;
  lookup.limit = static_cast<double>(lookup.last);
  lookup.first.assign(size_t(buckets) + 1, 0);
  for (double v : s) ++lookup.first[lookup.bucket(v) + 1];
  for (size_t b = 1; b < lookup.first.size(); ++b) lookup.first[b] += lookup.first[b - 1];
}

// Counting sort of points into cells, split into parts that own contiguous
// ranges of rows of cells (cells are stored z-major, then y, then x; quantile
// slabs hold about equal counts, so equal row ranges are balanced). Each part
// lists its points in increasing order, zeroes and counts its own cells, and
// turns the counts into cell ends with an inclusive prefix sum; after the
// parts' totals are known, a backward fill leaves cell starts behind. The
// result does not depend on the number of parts: within a cell, items are in
// increasing order.
void QuantileGrid::fill_points(const std::vector<Vec3>& centers, int threads) {
  constexpr size_t kMinPointsPerPart = 16384;
  const size_t n = centers.size();
  cell_of_.resize(n);
  // The slab searches are the expensive part, and independent per point.
  parallel_for(threads, n, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Vec3& p = centers[i];
      cell_of_[i] = (slab_index(2, p.z) * dims_[1] + slab_index(1, p.y)) * dims_[0] + slab_index(0, p.x);
    }
  });
  const size_t rows = size_t(dims_[1]) * dims_[2];
  const size_t parts = std::max<size_t>(1, std::min({size_t(std::max(threads, 1)), rows, n / kMinPointsPerPart}));
  auto first_cell = [&](size_t part) { return rows * part / parts * dims_[0]; };
  if (part_points_.size() < parts) part_points_.resize(parts);
  std::vector<size_t> part_begin(parts + 1, 0);  // where each part's items start in items_
  uint32_t* cell_begin = cell_begin_.data();
  const uint32_t* cell_of = cell_of_.data();
  parallel_each(static_cast<int>(parts), parts, [&](size_t part) {
    const size_t lo = first_cell(part), cells = first_cell(part + 1) - lo;
    FillVector<uint32_t>& mine = part_points_[part];
    mine.resize(n);
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {  // branch-free: which part a point is in looks random
      mine[count] = static_cast<uint32_t>(i);
      count += cell_of[i] - lo < cells;
    }
    mine.resize(count);
    std::fill(cell_begin + lo, cell_begin + lo + cells, 0u);
    for (uint32_t i : mine) ++cell_begin[cell_of[i]];
    uint32_t end = 0;
    for (size_t c = lo; c < lo + cells; ++c) cell_begin[c] = end += cell_begin[c];
    part_begin[part + 1] = count;
  });
  for (size_t part = 0; part < parts; ++part) part_begin[part + 1] += part_begin[part];
  items_.resize(n);
  parallel_each(static_cast<int>(parts), parts, [&](size_t part) {
    const size_t lo = first_cell(part), hi = first_cell(part + 1);
    uint32_t* items = items_.data() + part_begin[part];
    const FillVector<uint32_t>& mine = part_points_[part];
    for (size_t k = mine.size(); k-- > 0;) items[--cell_begin[cell_of[mine[k]]]] = mine[k];
    const uint32_t offset = static_cast<uint32_t>(part_begin[part]);
    for (size_t c = lo; c < hi; ++c) cell_begin[c] += offset;
  });
  cell_begin_.back() = static_cast<uint32_t>(n);
}

// Same counting sort over (sphere, cell) references. The slab ranges found in
// the counting pass are kept for the fill pass (24 bytes a sphere): looking
// them up twice cost a third of the build.
void QuantileGrid::fill_spheres(const std::vector<Vec3>& centers, const std::vector<double>& radii) {
  const size_t n = centers.size();
  struct Range {
    uint32_t lo[3], hi[3];
  };
  std::vector<Range> ranges(n);
  std::fill(cell_begin_.begin(), cell_begin_.end(), 0u);
  uint64_t total = 0;
  for (size_t i = 0; i < n; ++i) {
    Vec3 lo, hi;
    sphere_box(centers[i], radii[i], lo, hi);
    Range& r = ranges[i];
    for (int a = 0; a < 3; ++a) {
      r.lo[a] = slab_index(a, lo[a]);
      r.hi[a] = slab_index(a, hi[a]);
    }
    total += uint64_t(r.hi[0] - r.lo[0] + 1) * (r.hi[1] - r.lo[1] + 1) * (r.hi[2] - r.lo[2] + 1);
    if (total > kMaxIndex) throw std::length_error("QuantileGrid::build: too many references");
    for (uint32_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (uint32_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (uint32_t x = r.lo[0]; x <= r.hi[0]; ++x) ++cell_begin_[(z * dims_[1] + y) * dims_[0] + x];
  }
  for (size_t c = 1; c < cell_begin_.size(); ++c) cell_begin_[c] += cell_begin_[c - 1];
  items_.assign(total, 0);
  for (size_t i = n; i-- > 0;) {
    const Range& r = ranges[i];
    for (uint32_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (uint32_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (uint32_t x = r.lo[0]; x <= r.hi[0]; ++x)
          items_[--cell_begin_[(z * dims_[1] + y) * dims_[0] + x]] = static_cast<uint32_t>(i);
  }
  cell_begin_.back() = static_cast<uint32_t>(total);
}

size_t QuantileGrid::memory_bytes() const {
  size_t bytes = sizeof(*this) + (cell_begin_.capacity() + items_.capacity() + cell_of_.capacity()) * sizeof(uint32_t);
  for (const auto& p : part_points_) bytes += p.capacity() * sizeof(uint32_t);
  for (const auto& s : splits_) bytes += s.capacity() * sizeof(double);
  for (const auto& l : lookup_) bytes += l.first.capacity() * sizeof(uint32_t);
  return bytes;
}

size_t QuantileGrid::nonempty_cell_count() const {
  size_t count = 0;
  for (size_t c = 0; c + 1 < cell_begin_.size(); ++c) count += cell_begin_[c + 1] > cell_begin_[c];
  return count;
}

}  // namespace ppm
