// A voxel grid's bricks, table and trilinear lookup (see voxel_grid.h).
#include "shading/voxel_grid.h"

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
  std::vector<Coord> origins;
  const size_t c = static_cast<size_t>(channels);
  std::vector<float> brick(kBrickVoxels * c);
  for (int bz = 0; bz * kBrick < size[2]; ++bz)
    for (int by = 0; by * kBrick < size[1]; ++by)
      for (int bx = 0; bx * kBrick < size[0]; ++bx) {
        std::fill(brick.begin(), brick.end(), 0.0f);
        bool any = false;
        for (int x = 0; x < kBrick && bx * kBrick + x < size[0]; ++x)
          for (int y = 0; y < kBrick && by * kBrick + y < size[1]; ++y)
            for (int z = 0; z < kBrick && bz * kBrick + z < size[2]; ++z) {
              const size_t from = ((size_t(bz * kBrick + z) * size[1] + (by * kBrick + y)) * size[0] + bx * kBrick + x) * c;
              const size_t to = size_t(x * kBrick * kBrick + y * kBrick + z) * c;
              for (size_t k = 0; k < c; ++k) {
                brick[to + k] = values[from + k];
                any = any || brick[to + k] != 0.0f;
              }
            }
        if (!any) continue;  // the background's
        origins.push_back({bx * kBrick, by * kBrick, bz * kBrick});
        values_.insert(values_.end(), brick.begin(), brick.end());
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
}

glm::vec4 VoxelGrid::voxel(int i, int j, int k) const {
  const int bx = block_of(i) - block_lo_[0], by = block_of(j) - block_lo_[1], bz = block_of(k) - block_lo_[2];
  if (bx < 0 || by < 0 || bz < 0 || bx >= block_dims_[0] || by >= block_dims_[1] || bz >= block_dims_[2])
    return glm::vec4(0.0f);
  const int32_t block = blocks_[(size_t(bz) * block_dims_[1] + by) * block_dims_[0] + bx];
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
