// Image-based light (see environment.h): the luminance distribution, lookups and sampling.
#include "scene/environment.h"

#include "math/sphere_maps.h"

#include <algorithm>
#include <cmath>

namespace ppm {
namespace {

constexpr int kMaxGridWidth = 2048;
constexpr int kSamplesPerCellSide = 2;
constexpr double kDensityFloor = 1e-3;  // of the mean cell weight

// The world's latitude-longitude grid: u turns about +Z from +X, v climbs from
// the nadir (v = 0) to the zenith (v = 1).
Vec3 grid_direction(double u, double v) {
  const double phi = 2.0 * kPi * u, elevation = kPi * (v - 0.5);
  const double c = std::cos(elevation);
  return Vec3(c * std::cos(phi), c * std::sin(phi), std::sin(elevation));
}

Vec2 grid_uv(const Vec3& dir) {
  double u = std::atan2(dir.y, dir.x) / (2.0 * kPi);
  if (u < 0.0) u += 1.0;
  const double v = std::asin(std::clamp(dir.z, -1.0, 1.0)) / kPi + 0.5;
  return Vec2(std::min(u, std::nextafter(1.0, 0.0)), v);
}

// Solid angle per unit du dv at elevation cosine c: 2 pi * pi * c.
double solid_angle_density(double cos_elevation) { return 2.0 * kPi * kPi * cos_elevation; }

}  // namespace

Environment::Environment(const Texture* texture, const Mat3& world_to_texture, const Color& strength,
                         EnvironmentProjection projection)
    : texture_(texture), world_to_texture_(world_to_texture), strength_(strength), projection_(projection) {
  grid_width_ = std::clamp(texture->width(), 8, kMaxGridWidth);
  grid_height_ = std::max(4, grid_width_ / 2);
  std::vector<double> weights(static_cast<size_t>(grid_width_) * grid_height_);
  double sum = 0.0;
  for (int y = 0; y < grid_height_; ++y) {
    for (int x = 0; x < grid_width_; ++x) {
      Color mean(0.0);
      for (int sy = 0; sy < kSamplesPerCellSide; ++sy)
        for (int sx = 0; sx < kSamplesPerCellSide; ++sx)
          mean += radiance(grid_direction((x + (sx + 0.5) / kSamplesPerCellSide) / grid_width_,
                                          (y + (sy + 0.5) / kSamplesPerCellSide) / grid_height_));
      mean /= double(kSamplesPerCellSide * kSamplesPerCellSide);
      const double cos_elevation = std::cos(kPi * ((y + 0.5) / grid_height_ - 0.5));
      const double cell_solid_angle = solid_angle_density(cos_elevation) / (double(grid_width_) * grid_height_);
      integral_ += mean * cell_solid_angle;
      const double w = std::fmax(0.0, luminance(mean)) * cos_elevation;
      weights[static_cast<size_t>(y) * grid_width_ + x] = w;
      sum += w;
    }
  }
  if (!(sum > 0.0)) return;  // black: nothing to sample
  const double floor = kDensityFloor * sum / weights.size();
  for (double& w : weights) w += floor;
  distribution_ = Distribution2D(weights, grid_width_, grid_height_);
}

Color Environment::radiance(const Vec3& dir) const {
  const Vec3 local = world_to_texture_ * dir;
  const Vec2 uv = projection_ == EnvironmentProjection::Equirectangular ? equirectangular_uv(local)
                                                                        : mirror_ball_uv(local);
  return texture_->lookup(uv, true) * strength_;
}

bool Environment::sample(double u1, double u2, Vec3& dir, double& pdf) const {
  if (distribution_.empty()) return false;
  double pdf_uv;
  const Vec2 uv = distribution_.sample(u1, u2, pdf_uv);
  dir = grid_direction(uv.x, uv.y);
  const double cos_elevation = std::cos(kPi * (uv.y - 0.5));
  if (!(cos_elevation > 0.0)) return false;  // a pole: measure zero
  pdf = pdf_uv / solid_angle_density(cos_elevation);
  return pdf > 0.0 && std::isfinite(pdf);
}

double Environment::pdf(const Vec3& dir) const {
  if (distribution_.empty()) return 0.0;
  const Vec2 uv = grid_uv(dir);
  const double cos_elevation = std::sqrt(std::fmax(0.0, 1.0 - dir.z * dir.z));
  if (!(cos_elevation > 0.0)) return 0.0;
  return distribution_.pdf(uv) / solid_angle_density(cos_elevation);
}

}  // namespace ppm
