// Fixed hit points, streamed: the hit points of progressive photon mapping
// (Hachisuka et al. 2008), the same every pass, but made again band by band
// each pass (RenderContext::band_rows) instead of kept for the whole render.
// What stays is 36 bytes of float statistics per hit point (radius, photon
// count, flux) and 20 bytes per pixel (what its eye paths see directly and its
// direct light, which add up per pixel, transparency, its first hit point),
// against about 360 bytes a kept hit point; the price is an eye pass every
// pass.
//
// The eye pass draws the same random numbers for a band as for those rows of
// the whole image (eye_pass.h), so every pass makes the same hit points in the
// same order: hit point i of a band is statistics record first[band] + i. A
// first eye pass in prepare() counts them per pixel and records what the eye
// paths see directly (emission, background, transparency), which no later
// pass changes. Direct light draws hit point i's random numbers as kept fixed
// hit points do, so both find the same image up to float statistics.
//
// A cancelled pass keeps the bands it completed and resumes at the next one,
// as with stochastic hit points.
#pragma once

#include "ppm/estimator.h"
#include "ppm/pixel_stats.h"

#include <vector>

namespace ppm {


class StreamedHitPoints : public Estimator {
 public:
  explicit StreamedHitPoints(RenderContext& context) : c_(context) { c_.stats.hit_point_storage = "streamed"; }
  bool prepare(const Poll& poll) override;
  bool pass(const Poll& poll) override;
  PixelValue pixel(size_t p) const override;
  SeenLight seen(size_t p) const override { return seen_.empty() ? SeenLight{} : seen_[p]; }
  double radius_mean() const override;
  ErrorPasses error_passes() const override {
    return ErrorPasses{c_.stats.passes, static_cast<size_t>(current_.next_row) * c_.scene->camera().width};
  }
  double pass_done() const override;
  void add_memory(MemoryUse& use) const override;

 private:
  struct PassInProgress {
    int next_row = 0;             // 0: no pass in progress
    PhotonPassCounters counters;  // the stats' photon counters once the pass completes
    double sum_r2 = 0.0;          // of the hit points folded so far: the next pass's typical radius
  };

  void check_memory_for(double hit_points) const;
  bool count_hit_points(const Poll& poll, double& mean_radius);
  bool band(const EyePassOptions& eye, uint64_t pass, const Poll& poll);
  void start_at_kept_radii(size_t first);
  double mean_r2_of_band() const;
  bool direct_light_due() const;
  void fold_band(size_t first);

  RenderContext& c_;
  FillVector<FloatPhotonStats> stats_;  // per hit point, in the eye pass's order
  std::vector<uint32_t> first_;        // per pixel and one more: its first hit point's record
  std::vector<Vec3f> light_;           // per pixel: what eye paths see directly, plus the mean direct light
  std::vector<float> transparency_;    // per pixel
  std::vector<SeenLight> seen_;        // per pixel, with settings.light_passes: the same every pass
  PassInProgress current_;
  double typical_r2_ = 0.0;            // mean r^2 of the last pass (sizes a hashed grid's cells)
  double initial_radius_sum_ = 0.0;    // over the first pass (stats' initial_radius_mean)
  HitPoints hit_points_;               // the band being made, reused
  EyePassScratch eye_scratch_;
  std::vector<double> block_sums_;     // fold_band's, kept so that no pass allocates
};

}  // namespace ppm
