// A piecewise-constant density over [0, 1)^2 on a grid of cells with given
// non-negative weights: a row by its marginal, then a cell within the row, then
// a uniform point in the cell (inverse transform of each CDF; no rejection).
#pragma once

#include "math/types.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ppm {

class Distribution2D {
 public:
  Distribution2D() = default;
  // `weights`: width * height values, row by row, row 0 at v in [0, 1/height).
  Distribution2D(const std::vector<double>& weights, int width, int height)
      : width_(width), height_(height), cdf_(weights.size()), row_cdf_(height) {
    double total = 0.0;
    for (int y = 0; y < height; ++y) {
      double row = 0.0;
      for (int x = 0; x < width; ++x) {
        row += weights[static_cast<size_t>(y) * width + x];
        cdf_[static_cast<size_t>(y) * width + x] = row;
      }
      total += row;
      row_cdf_[y] = total;
    }
    total_ = total;
  }

  bool empty() const { return !(total_ > 0.0); }

  // A point with density pdf (with respect to du dv). Only for a non-empty distribution.
  Vec2 sample(double u1, double u2, double& pdf) const {
    double fy;
    const int y = pick(row_cdf_.data(), height_, u2 * total_, fy);
    const double* row = &cdf_[static_cast<size_t>(y) * width_];
    double fx;
    const int x = pick(row, width_, u1 * row[width_ - 1], fx);
    pdf = weight(x, y) / total_ * width_ * height_;
    return Vec2((x + fx) / width_, (y + fy) / height_);
  }

  double pdf(const Vec2& uv) const {
    const int x = std::clamp(static_cast<int>(uv.x * width_), 0, width_ - 1);
    const int y = std::clamp(static_cast<int>(uv.y * height_), 0, height_ - 1);
    return weight(x, y) / total_ * width_ * height_;
  }

 private:
  double weight(int x, int y) const {
    const size_t i = static_cast<size_t>(y) * width_ + x;
    return cdf_[i] - (x > 0 ? cdf_[i - 1] : 0.0);
  }

  // The first entry of the running sum `cdf` (n entries) above `target`, and
  // where in that entry's step the target lies (in [0, 1)). Zero-weight
  // entries are never picked.
  static int pick(const double* cdf, int n, double target, double& fraction) {
    int i = static_cast<int>(std::upper_bound(cdf, cdf + n, target) - cdf);
    i = std::min(i, n - 1);
    while (i > 0 && !(cdf[i] > cdf[i - 1])) --i;  // target rounded up to the total: the last with weight
    const double below = i > 0 ? cdf[i - 1] : 0.0;
    fraction = std::clamp((target - below) / (cdf[i] - below), 0.0, std::nextafter(1.0, 0.0));
    return i;
  }

  int width_ = 0, height_ = 0;
  std::vector<double> cdf_;      // running sum within each row
  std::vector<double> row_cdf_;  // running sum of the row totals
  double total_ = 0.0;
};

}  // namespace ppm
