// A voxel grid's bricks, table and trilinear lookup (see voxel_grid.h).
#include "shading/voxel_grid.h"

#include "math/aabb.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ppm {

namespace {
constexpr long long kMaxAxis = 8192;
constexpr long long kMaxValues = 1LL << 30;       // 4 GiB of floats
constexpr long long kMaxBlockEntries = 1LL << 27;  // 512 MiB of block table: a box 65,536 voxels a side

int floor_div(int i, int n) { return i >= 0 ? i / n : -((-i + n - 1) / n); }
int brick_of(int i) { return floor_div(i, VoxelGrid::kBrick); }
int block_of(int i) { return floor_div(i, VoxelGrid::kBrick * VoxelGrid::kBlock); }
int in_brick(int i) { return i & (VoxelGrid::kBrick - 1); }  // (two's complement: right for negatives too)
int place_in_block(int i) { return brick_of(i) & (VoxelGrid::kBlock - 1); }
}  // namespace

void check_grid_shape(std::array<long long, 3> size, int channels, const std::string& what) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(what + ": " + why); };
  if (channels != 1 && channels != 3 && channels != 4) fail("a grid has 1, 3 or 4 channels");
  long long values = channels;
  for (long long n : size) {
    if (n < 1 || n > kMaxAxis) fail("a grid's size along each axis must be 1 to " + std::to_string(kMaxAxis));
    values *= n;
  }
  if (values > kMaxValues) fail("a grid of more than 2^30 values is not supported");
}

namespace {
Mat4 unit_box_to_index(const VoxelGrid::Coord& size) {
  Mat4 m(1.0);
  for (int k = 0; k < 3; ++k) {
    m[k][k] = double(size[k]);
    m[3][k] = -0.5;
  }
  return m;
}
}  // namespace

VoxelGrid::VoxelGrid(Coord size, int channels, const float* values)
    : VoxelGrid(size, channels, values, unit_box_to_index(size)) {}

VoxelGrid::VoxelGrid(Coord size, int channels, const float* values, const Mat4& to_index) : channels_(channels) {
  check_grid_shape({size[0], size[1], size[2]}, channels, "voxel grid");
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(to_index[r][k])) throw std::invalid_argument("voxel grid: its transform is not finite");
  to_index_ = glm::mat4(to_index);
  const size_t c = static_cast<size_t>(channels);
  // A brick's voxels in its place of a dense grid (x fastest) and of a brick (z fastest), for each
  // voxel of the brick at (bx, by, bz) inside the grid.
  auto for_each_voxel = [&](int bx, int by, int bz, auto&& visit) {
    for (int x = 0; x < kBrick && bx * kBrick + x < size[0]; ++x)
      for (int y = 0; y < kBrick && by * kBrick + y < size[1]; ++y)
        for (int z = 0; z < kBrick && bz * kBrick + z < size[2]; ++z)
          visit(((size_t(bz * kBrick + z) * size[1] + (by * kBrick + y)) * size[0] + bx * kBrick + x) * c,
                size_t(x * kBrick * kBrick + y * kBrick + z) * c);
  };
  // The bricks holding anything (an empty one is the background's), then exactly their values.
  std::vector<Coord> origins;
  for (int bz = 0; bz * kBrick < size[2]; ++bz)
    for (int by = 0; by * kBrick < size[1]; ++by)
      for (int bx = 0; bx * kBrick < size[0]; ++bx) {
        bool any = false;
        for_each_voxel(bx, by, bz, [&](size_t from, size_t) {
          for (size_t k = 0; k < c; ++k) any = any || values[from + k] != 0.0f;
        });
        if (any) origins.push_back({bx * kBrick, by * kBrick, bz * kBrick});
      }
  values_.assign(origins.size() * kBrickVoxels * c, 0.0f);
  for (size_t b = 0; b < origins.size(); ++b) {
    float* brick = values_.data() + b * kBrickVoxels * c;
    for_each_voxel(origins[b][0] / kBrick, origins[b][1] / kBrick, origins[b][2] / kBrick, [&](size_t from, size_t to) {
      for (size_t k = 0; k < c; ++k) brick[to + k] = values[from + k];
    });
  }
  bricks_ = origins.size();
  constants_at_ = values_.size();
  store(values_.data(), values_.size(), channels == 4);
  make_table(origins, {}, "voxel grid");
}

VoxelGrid::VoxelGrid(int channels, const Mat4& to_index, const std::vector<Coord>& origins, const float* values,
                     const std::vector<Coord>& constant_origins, const float* constant_values,
                     const std::string& what)
    : channels_(channels), to_index_(glm::mat4(to_index)), bricks_(origins.size()) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(what + ": " + why); };
  if (channels != 1 && channels != 3 && channels != 4) fail("a grid has 1, 3 or 4 channels");
  if ((origins.size() * kBrickVoxels + constant_origins.size()) * size_t(channels) > size_t(kMaxValues))
    fail("a grid of more than 2^30 values is not supported");
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(to_index[r][k])) fail("its transform is not finite");
  const size_t c = static_cast<size_t>(channels);
  values_.reserve((origins.size() * kBrickVoxels + constant_origins.size()) * c);  // exactly: no growth's slack
  values_.assign(values, values + origins.size() * kBrickVoxels * c);
  constants_at_ = values_.size();
  values_.insert(values_.end(), constant_values, constant_values + constant_origins.size() * c);
  store(values_.data(), values_.size(), channels == 4);
  make_table(origins, constant_origins, what);
}

void VoxelGrid::store(float* v, size_t count, bool alpha_last) {
  float most = 0.0f, alpha = alpha_last ? 0.0f : 1.0f;
  for (size_t i = 0; i < count; ++i) {
    if (!std::isfinite(v[i])) {
      v[i] = 0.0f;
      ++not_finite_;
    }
    if (alpha_last && i % 4 == 3)
      alpha = std::max(alpha, v[i]);
    else
      most = std::max(most, v[i]);
  }
  max_value_ = most;
  max_alpha_ = alpha;
  // Each brick's (and constant's) largest colour value, for max_in.
  const size_t c = static_cast<size_t>(channels_), colours = c == 4 ? 3 : c;
  const size_t per_brick = size_t(kBrickVoxels) * c;
  brick_max_.assign(bricks_ + (count - constants_at_) / c, 0.0f);
  for (size_t i = 0; i < count; ++i) {
    const size_t b = i < constants_at_ ? i / per_brick : bricks_ + (i - constants_at_) / c;
    if (i % c < colours) brick_max_[b] = std::max(brick_max_[b], v[i]);
  }
}

void VoxelGrid::make_table(const std::vector<Coord>& origins, const std::vector<Coord>& constant_origins,
                           const std::string& what) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(what + ": " + why); };
  constexpr int kMin = std::numeric_limits<int>::min(), kMax = std::numeric_limits<int>::max();
  Coord lo{kMax, kMax, kMax}, hi{kMin, kMin, kMin}, block_lo = lo, block_hi = hi;
  auto extend = [&](const Coord& o) {
    for (int k = 0; k < 3; ++k) {
      if (in_brick(o[k]) != 0) fail("a brick's origin is not a multiple of 8");
      if (o[k] > kMax - kBrick) fail("a brick's origin is out of range");
      lo[k] = std::min(lo[k], o[k]), hi[k] = std::max(hi[k], o[k] + kBrick);
      block_lo[k] = std::min(block_lo[k], block_of(o[k])), block_hi[k] = std::max(block_hi[k], block_of(o[k]));
    }
  };
  for (const Coord& o : origins) extend(o);
  for (const Coord& o : constant_origins) extend(o);
  if (origins.empty() && constant_origins.empty()) return;  // empty: everything reads 0
  long long entries = 1;
  for (int k = 0; k < 3; ++k) entries *= static_cast<long long>(block_hi[k]) - block_lo[k] + 1;
  if (entries > kMaxBlockEntries) fail("its bricks spread over more than 2^27 blocks of 128^3 voxels");
  lo_ = lo, hi_ = hi, block_lo_ = block_lo;
  block_dims_ = {block_hi[0] - block_lo[0] + 1, block_hi[1] - block_lo[1] + 1, block_hi[2] - block_lo[2] + 1};
  blocks_.assign(static_cast<size_t>(entries), -1);
  auto place = [&](const Coord& o) -> int32_t& {
    int32_t& block = blocks_[(size_t(block_of(o[2]) - block_lo_[2]) * block_dims_[1] +
                              size_t(block_of(o[1]) - block_lo_[1])) * block_dims_[0] +
                             size_t(block_of(o[0]) - block_lo_[0])];
    if (block < 0) {
      block = static_cast<int32_t>(places_.size() / kBlockPlaces);
      places_.resize(places_.size() + kBlockPlaces, -1);
    }
    const size_t in = (size_t(place_in_block(o[2])) * kBlock + place_in_block(o[1])) * kBlock + place_in_block(o[0]);
    return places_[size_t(block) * kBlockPlaces + in];
  };
  for (size_t b = 0; b < origins.size(); ++b) place(origins[b]) = static_cast<int32_t>(b);
  for (size_t t = 0; t < constant_origins.size(); ++t) place(constant_origins[t]) = -2 - int32_t(t);
  places_.shrink_to_fit();  // (grown block by block)
}

int32_t VoxelGrid::block_at(int x, int y, int z) const {
  x -= block_lo_[0], y -= block_lo_[1], z -= block_lo_[2];
  if (x < 0 || y < 0 || z < 0 || x >= block_dims_[0] || y >= block_dims_[1] || z >= block_dims_[2]) return -1;
  return blocks_[(size_t(z) * block_dims_[1] + size_t(y)) * block_dims_[0] + size_t(x)];
}

glm::vec4 VoxelGrid::voxel(int i, int j, int k) const {
  const int32_t block = block_at(block_of(i), block_of(j), block_of(k));
  if (block < 0) return glm::vec4(0.0f);
  const int32_t entry = places_[size_t(block) * kBlockPlaces +
                                (size_t(place_in_block(k)) * kBlock + place_in_block(j)) * kBlock + place_in_block(i)];
  if (entry == -1) return glm::vec4(0.0f);
  const size_t c = static_cast<size_t>(channels_);
  const float* v = entry >= 0 ? values_.data() + (size_t(entry) * kBrickVoxels +
                                                  size_t(in_brick(i) * kBrick * kBrick + in_brick(j) * kBrick +
                                                         in_brick(k))) * c
                              : values_.data() + constants_at_ + size_t(-2 - entry) * c;
  if (c == 1) return glm::vec4(v[0], v[0], v[0], 1.0f);
  return glm::vec4(v[0], v[1], v[2], c == 4 ? v[3] : 1.0f);
}

float VoxelGrid::max_in(const Vec3& lo, const Vec3& hi) const {
  if (blocks_.empty()) return 0.0f;
  if (!is_finite(lo) || !is_finite(hi)) return max_value_;
  // The box in index space (its eight corners through the transform), widened by a thousandth of
  // a voxel against rounding (lookup transforms in float); a lookup there reads the voxels from
  // floor(q) to floor(q) + 1.
  const Aabb index_box = transformed(Aabb{lo, hi}, glm::dmat4(to_index_));
  const Vec3 &ilo = index_box.lo, &ihi = index_box.hi;
  Coord first{}, last{};
  for (int k = 0; k < 3; ++k) {
    const double margin = 1e-3 + 1e-6 * std::max(std::fabs(ilo[k]), std::fabs(ihi[k]));
    const double a = std::max(std::floor(ilo[k] - margin), double(lo_[k]) - 1.0);
    const double b = std::min(std::floor(ihi[k] + margin) + 1.0, double(hi_[k]));
    if (!(a <= b)) return 0.0f;  // outside every brick
    first[k] = brick_of(int(a)), last[k] = brick_of(int(b));
  }
  // Block by block (an absent one holds nothing), then the brick places of each that the box covers.
  float most = 0.0f;
  Coord block_first{}, block_last{};
  for (int k = 0; k < 3; ++k) {
    block_first[k] = std::max(floor_div(first[k], kBlock), block_lo_[k]);
    block_last[k] = std::min(floor_div(last[k], kBlock), block_lo_[k] + block_dims_[k] - 1);
  }
  for (int kz = block_first[2]; kz <= block_last[2]; ++kz)
    for (int ky = block_first[1]; ky <= block_last[1]; ++ky)
      for (int kx = block_first[0]; kx <= block_last[0]; ++kx) {
        const int32_t block = block_at(kx, ky, kz);
        if (block < 0) continue;
        const int32_t* places = places_.data() + size_t(block) * kBlockPlaces;
        const Coord at{kx * kBlock, ky * kBlock, kz * kBlock};
        Coord from{}, to{};
        for (int k = 0; k < 3; ++k)
          from[k] = std::max(first[k], at[k]) - at[k], to[k] = std::min(last[k], at[k] + kBlock - 1) - at[k];
        for (int z = from[2]; z <= to[2]; ++z)
          for (int y = from[1]; y <= to[1]; ++y)
            for (int x = from[0]; x <= to[0]; ++x) {
              const int32_t entry = places[(size_t(z) * kBlock + size_t(y)) * kBlock + size_t(x)];
              if (entry != -1) most = std::max(most, brick_max_[entry >= 0 ? size_t(entry) : bricks_ + size_t(-2 - entry)]);
            }
      }
  return most;
}

size_t VoxelGrid::regions_4096() const {
  constexpr int kBlocksPerRegion = 4096 / (kBrick * kBlock);
  std::vector<Coord> regions;
  for (int z = block_lo_[2]; z < block_lo_[2] + block_dims_[2]; ++z)
    for (int y = block_lo_[1]; y < block_lo_[1] + block_dims_[1]; ++y)
      for (int x = block_lo_[0]; x < block_lo_[0] + block_dims_[0]; ++x)
        if (block_at(x, y, z) >= 0)
          regions.push_back({floor_div(x, kBlocksPerRegion), floor_div(y, kBlocksPerRegion), floor_div(z, kBlocksPerRegion)});
  std::sort(regions.begin(), regions.end());
  return size_t(std::unique(regions.begin(), regions.end()) - regions.begin());
}

namespace {
float lcg_uniform(uint32_t* state) {  // (Numerical Recipes' LCG, its top 24 bits)
  *state = *state * 1664525u + 1013904223u;
  return float(*state >> 8) * (1.0f / 16777216.0f);
}
}  // namespace

glm::vec4 VoxelGrid::lookup(const Vec3f& p, uint32_t* state) const {
  const glm::vec4 q = to_index_ * glm::vec4(p, 1.0f);
  constexpr float kFar = 1e9f;  // beyond any table (and not finite): 0, before the casts to int
  if (!(std::fabs(q.x) < kFar && std::fabs(q.y) < kFar && std::fabs(q.z) < kFar)) return glm::vec4(0.0f);
  const float fx = std::floor(q.x), fy = std::floor(q.y), fz = std::floor(q.z);
  const int i = static_cast<int>(fx), j = static_cast<int>(fy), k = static_cast<int>(fz);
  const float ax = q.x - fx, ay = q.y - fy, az = q.z - fz;
  if (stochastic_ && state != nullptr)
    return voxel(i + (lcg_uniform(state) < ax), j + (lcg_uniform(state) < ay), k + (lcg_uniform(state) < az));
  auto along_x = [&](int jj, int kk) { return voxel(i, jj, kk) * (1.0f - ax) + voxel(i + 1, jj, kk) * ax; };
  const glm::vec4 near = along_x(j, k) * (1.0f - ay) + along_x(j + 1, k) * ay;
  const glm::vec4 far = along_x(j, k + 1) * (1.0f - ay) + along_x(j + 1, k + 1) * ay;
  return near * (1.0f - az) + far * az;
}

}  // namespace ppm
