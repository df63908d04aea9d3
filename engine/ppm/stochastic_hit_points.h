// Stochastic progressive photon mapping (Hachisuka & Jensen 2009): every pass
// draws new eye samples, gathers the pass's photons at them with their pixel's
// current radius, and folds them into the pixel's statistics with the same
// progressive update.
#pragma once

#include "ppm/estimator.h"
#include "ppm/pixel_stats.h"

#include <vector>

namespace ppm {

class StochasticHitPoints : public Estimator {
 public:
  explicit StochasticHitPoints(RenderContext& context) : c_(context) {}
  bool prepare(const Poll& poll) override;
  bool pass(const Poll& poll) override;
  PixelValue pixel(size_t p) const override;
  double radius_mean() const override;
  size_t memory_bytes() const override;

 private:
  void start_at_pixel_radii(HitPoints& fresh);
  void fold_into_pixels(const HitPoints& fresh);

  RenderContext& c_;
  std::vector<PixelStats> pixels_;
  HitPoints hit_points_;  // the pass being made, reused: no pass allocates once sizes settle
};

}  // namespace ppm
