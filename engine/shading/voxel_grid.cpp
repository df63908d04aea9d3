// A dense voxel grid's storage and trilinear lookup (see voxel_grid.h).
#include "shading/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ppm {

namespace {
constexpr long long kMaxAxis = 8192;
constexpr long long kMaxValues = 1LL << 30;  // 4 GiB of floats
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

VoxelGrid::VoxelGrid(std::array<int, 3> size, int channels, const float* values)
    : size_(size), channels_(channels) {
  check_grid_shape({size[0], size[1], size[2]}, channels, "voxel grid");
  values_.assign(values, values + voxels() * static_cast<size_t>(channels));
  float most = 0.0f, alpha = channels == 4 ? 0.0f : 1.0f;
  for (size_t i = 0; i < values_.size(); ++i) {
    float& v = values_[i];
    if (!std::isfinite(v)) {
      v = 0.0f;
      ++not_finite_;
    }
    if (channels == 4 && i % 4 == 3)
      alpha = std::max(alpha, v);
    else
      most = std::max(most, v);
  }
  max_value_ = most;
  max_alpha_ = alpha;
}

glm::vec4 VoxelGrid::voxel(int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i >= size_[0] || j >= size_[1] || k >= size_[2]) return glm::vec4(0.0f);
  const size_t at = ((static_cast<size_t>(k) * size_[1] + j) * size_[0] + i) * channels_;
  const float* v = values_.data() + at;
  if (channels_ == 1) return glm::vec4(v[0], v[0], v[0], 1.0f);
  return glm::vec4(v[0], v[1], v[2], channels_ == 4 ? v[3] : 1.0f);
}

glm::vec4 VoxelGrid::lookup(const Vec3f& p) const {
  const float x = p.x * size_[0] - 0.5f, y = p.y * size_[1] - 0.5f, z = p.z * size_[2] - 0.5f;
  if (!(x > -1.0f && y > -1.0f && z > -1.0f && x < size_[0] && y < size_[1] && z < size_[2]))
    return glm::vec4(0.0f);  // (NaN too)
  const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const int i = static_cast<int>(fx), j = static_cast<int>(fy), k = static_cast<int>(fz);
  const float ax = x - fx, ay = y - fy, az = z - fz;
  auto along_x = [&](int jj, int kk) { return voxel(i, jj, kk) * (1.0f - ax) + voxel(i + 1, jj, kk) * ax; };
  const glm::vec4 near = along_x(j, k) * (1.0f - ay) + along_x(j + 1, k) * ay;
  const glm::vec4 far = along_x(j, k + 1) * (1.0f - ay) + along_x(j + 1, k + 1) * ay;
  return near * (1.0f - az) + far * az;
}

}  // namespace ppm
