// Progressive photon mapping with fixed hit points (Hachisuka et al. 2008):
// one eye pass records the hit points, every photon pass adds to their
// statistics, and a pixel is the sum of its hit points' estimates. The hit
// points are kept for the whole render; streamed_hit_points.h makes them again
// every pass instead, where they would not fit in memory.
#pragma once

#include "ppm/estimator.h"

namespace ppm {

// What kept fixed hit points will hold at their peak, all included (checked before the eye pass).
double kept_hit_point_bytes(const Camera& camera, int samples_per_pixel, bool components);

class FixedHitPoints : public Estimator {
 public:
  explicit FixedHitPoints(RenderContext& context) : c_(context) { c_.stats.hit_point_storage = "kept"; }
  bool prepare(const Poll& poll) override;
  bool pass(const Poll& poll) override;
  PixelValue pixel(size_t p) const override;
  SeenLight seen(size_t p) const override { return hit_points_.seen.empty() ? SeenLight{} : hit_points_.seen[p]; }
  ComponentLight components(size_t p) const override;
  bool has_components() const override { return true; }
  double radius_mean() const override;
  ErrorPasses error_passes() const override { return ErrorPasses{c_.stats.passes, 0}; }
  const std::vector<float>& sampling_variance() const override;
  void add_memory(MemoryUse& use) const override {
    use.hit_points += hit_points_.memory_bytes() - hit_points_.pixel_bytes();
    use.pixels += hit_points_.pixel_bytes() + (errors_.capacity() * sizeof(PixelErrorStats)) +
                  sampling_variance_.capacity() * sizeof(float);
  }

 private:
  void check_memory_for_hit_points() const;
  void widen_to_photon_spacing();
  void report_empty_pixels();
  void update_pixels(bool direct_sampled);

  RenderContext& c_;
  HitPoints hit_points_;
  // sampling_variance()'s, made when asked after a pass, kept until the next.
  mutable std::vector<float> sampling_variance_;
  mutable uint64_t sampling_variance_passes_ = 0;
};

}  // namespace ppm
