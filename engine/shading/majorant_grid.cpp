// A majorant grid's mean and its walk along a ray (3-D DDA, Amanatides & Woo 1987).
#include "shading/majorant_grid.h"

#include <algorithm>
#include <cmath>

namespace ppm {

double MajorantGrid::mean_majorant() const {
  double sum = 0.0;
  for (const Cell& c : cells_) sum += c.majorant;
  return cells_.empty() ? 0.0 : sum / double(cells_.size());
}

MajorantGrid::Walk::Walk(const MajorantGrid& grid, const Ray& ray) : grid_(&grid) {
  // The line's stretch in the box, t >= 0 (a direction along an axis inside the slab: all of it).
  double enter = 0.0, leave = kInf;
  if (!is_finite(ray.origin) || !is_finite(ray.direction)) leave = -1.0;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[a], d = ray.direction[a];
    if (d == 0.0) {
      if (!(o >= grid.box_.lo[a] && o <= grid.box_.hi[a])) leave = -1.0;
      continue;
    }
    double tn = (grid.box_.lo[a] - o) / d, tf = (grid.box_.hi[a] - o) / d;
    if (tn > tf) std::swap(tn, tf);
    enter = std::max(enter, tn), leave = std::min(leave, tf);
  }
  if (!(enter <= leave) || !(leave > 0.0) || !(enter < kInf)) {
    stage_ = 2;  // the box is not on the ray (or the numbers are not finite)
    return;
  }
  t_enter_ = enter, t_leave_ = leave;
  stage_ = enter > 0.0 ? 0 : 1;
  const Vec3 p = ray.origin + enter * ray.direction;
  for (int a = 0; a < 3; ++a) {
    const double size = grid.cell_[a], d = ray.direction[a];
    const double at = size > 0.0 ? std::floor((p[a] - grid.box_.lo[a]) / size) : 0.0;
    at_[a] = std::clamp(std::isfinite(at) ? int(std::clamp(at, -1.0, double(grid.dims_[a]))) : 0, 0, grid.dims_[a] - 1);
    if (d == 0.0 || !(size > 0.0)) continue;  // never leaves its cell along this axis
    step_[a] = d > 0.0 ? 1 : -1;
    const double boundary = grid.box_.lo[a] + (at_[a] + (d > 0.0 ? 1 : 0)) * size;
    t_next_[a] = (boundary - ray.origin[a]) / d;
    t_delta_[a] = size / std::fabs(d);
  }
}

MajorantGrid::Piece MajorantGrid::Walk::next() {
  if (stage_ == 0) {
    stage_ = 1;
    t_ = t_enter_;
    return {t_enter_, &grid_->outside_};
  }
  if (stage_ == 2) return {kInf, &grid_->outside_};
  const int axis = t_next_.x < t_next_.y ? (t_next_.x < t_next_.z ? 0 : 2) : (t_next_.y < t_next_.z ? 1 : 2);
  const double end = std::max(std::min(t_next_[axis], t_leave_), t_);  // never backwards
  const Piece piece{end, &grid_->cells_[grid_->index(at_[0], at_[1], at_[2])]};
  t_ = end;
  at_[axis] += step_[axis];
  t_next_[axis] += t_delta_[axis];
  if (!(end < t_leave_) || at_[axis] < 0 || at_[axis] >= grid_->dims_[axis]) stage_ = 2;
  return piece;
}

}  // namespace ppm
