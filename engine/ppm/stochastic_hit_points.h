// Stochastic progressive photon mapping (Hachisuka & Jensen 2009): every pass
// draws new eye samples, gathers the pass's photons at them with their pixel's
// current radius, and folds them into the pixel's statistics with the same
// progressive update.
//
// A pass traces and indexes its photons once, then makes its hit points band
// by band (rows of about RenderContext::kBandPixels pixels): each band's eye pass, gather and
// direct light, folded into its pixels. Memory for hit points is then one
// band's, whatever the image size; what grows with the image is the pixels'
// statistics (pixel_stats.h). The hit-point-indexed gather needs every hit
// point before the photons fly: it takes the image as one band.
//
// With the global radius schedule (radius_schedule.h) a pixel keeps only the mean of its pass values,
// and a renderer may start at any pass of a still (settings.first_pass): a share (share.h).
//
// A cancelled pass keeps the bands it completed and resumes at the next one
// (the pass's photons stay indexed), so the image is the same as without the
// cancel; meanwhile each pixel shows the passes folded into it.
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
  SeenLight seen(size_t p) const override;
  ComponentLight components(size_t p) const override;
  bool has_components() const override { return true; }
  double radius_mean() const override;
  ErrorPasses error_passes() const override {
    return ErrorPasses{c_.stats.passes, static_cast<size_t>(current_.next_row) * c_.scene->camera().width};
  }
  double pass_done() const override;
  void add_memory(MemoryUse& use) const override;

 private:
  // The pass in progress: where it resumes after a cancel.
  struct PassInProgress {
    int next_row = 0;                // 0: no pass in progress
    PhotonPassCounters counters;     // the stats' photon counters once the pass completes
    uint64_t hit_points = 0;         // made so far; numbers the next band's (their random numbers)
  };

  // One band of rows (eye.row_begin to eye.row_end) of pass `pass`, folded into its pixels.
  bool band(const EyePassOptions& eye, uint64_t pass, const Poll& poll);
  bool gather_photons(bool first_band, uint64_t pass, const Poll& poll);
  void start_at_pixel_radii(size_t first_pixel);
  void start_at_global_radii(size_t first_pixel, uint64_t index);
  void fold_band(size_t first_pixel, uint64_t pass, const uint8_t* pixel_samples);
  void fold_band_global(size_t first_pixel, uint64_t pass);
  void fold_seen(size_t pixel, size_t band_pixel, uint64_t pass);
  // Scenes with media: the band's hit points in media at their pixels' volume radii, their photons
  // and direct light, summed per band pixel into volume_band_, then folded into volume_pixels_.
  bool volume_band(size_t first_pixel, uint64_t pass, const uint8_t* pixel_samples, const Poll& poll);
  void start_volume_at_global_radii(uint64_t index);
  void sum_volume_band(size_t first_pixel);
  // With Settings::volume_beams: the band's beams at their pixels' beam radii (the 2-D rule: a
  // pixel's beams share one radius, as its surface hit points do) or the global schedule's, their
  // photons summed per band pixel into beam_band_, then folded into beam_pixels_.
  // start_beams (before the hit points in media gather) sets the radii and which beams gather.
  void start_beams(uint64_t pass);
  bool beam_band(size_t first_pixel, const uint8_t* pixel_samples, const Poll& poll);
  void sum_beam_band(size_t first_pixel);
  // The photons the pass in progress has emitted: what the band's findings are estimates over.
  double pass_photons() const { return static_cast<double>(current_.counters.emitted - c_.stats.photon.emitted); }
  float density_form(const VolumeHitPoint& h) const;
  // With component passes: band pixel p's hit points in media's direct light, and (the global
  // schedule) their photons' radiance this pass, into `light` by component (light_components.h).
  void add_volume_direct(size_t p, ComponentLight& light) const;
  void add_volume_radiance(size_t p, ComponentLight& light) const;
  // Band pixel p's hit points in media's photon radiance this pass, in luminance: their part of the
  // pass's value in the error estimate (their direct light is in the pixel's `emitted` already).
  // With the progressive radii it is what they add to the pixel's volume estimate: tau / r^3 is
  // unchanged by the 3-D update as tau / r^2 by the 2-D one (error_estimate.h).
  // Beams' radiance (gathered in a disc across them) is added the same way.
  double volume_pass_value(size_t p) const {
    if (!media_) return 0.0;
    return luminance(Color(volume_band_[p].radiance)) + (beams_ ? luminance(Color(beam_band_[p].radiance)) : 0.0);
  }
  double volume_pass_bias(size_t p) const {
    return media_ ? volume_band_[p].bias + (beams_ ? beam_band_[p].bias : 0.0) : 0.0;
  }
  template <class Scale>
  void pass_components(size_t p, ComponentLight& light, Vec3f photons[], Scale&& photon_scale) const;
  // The index in the still of this renderer's pass `pass` (its random numbers and global radius).
  uint64_t index(uint64_t pass) const { return c_.settings.first_pass + pass; }

  RenderContext& c_;
  std::vector<PixelStats> pixels_;
  PassInProgress current_;
  std::vector<float> depth_;  // the pass's depth (POST depth of field), until it completes
  std::vector<uint8_t> eye_samples_;  // per pixel, the pass's eye samples (adaptive_samples.h)
  // With settings.light_passes, per pixel: the running means of what camera rays saw at no bounce.
  struct SeenMeans {
    Vec3f emission, environment;
  };
  std::vector<SeenMeans> seen_;
  std::vector<PixelComponents> components_;  // with settings.component_passes (light_components.h)
  // Scenes with media: per pixel, the photon statistics of its hit points in media (the 3-D rule,
  // progressive.h; none with the global schedule), and per band pixel what the band's hit points in
  // media found: photons, their flux and its radiance this pass, direct light.
  // A pixel's hit points in media lie at many depths (fog the camera is in: from its lens to the
  // far wall), each with a radius of its own footprint; so a volume pixel's r2 is no radius but the
  // shrink s^2 of all of them (1 at first), and its tau their flux in density form (density_form).
  // Sharing the first hit point's radius instead left a pixel whose first lay near the lens a
  // radius that gathers next to nothing everywhere else: fireflies.
  bool media_ = false;
  std::vector<FloatPhotonStats> volume_pixels_;
  struct VolumeFound {
    uint32_t m;
    Vec3f tau, direct, radiance;
    float bias;  // the photons' bias estimate this pass, in luminance (error_estimate.h)
  };
  std::vector<VolumeFound> volume_band_;
  // With component passes too: per band pixel the same by slot (light_components.h), and per pixel
  // (progressive radii) the volume photons' flux by slot.
  struct VolumeParts {
    Vec3f direct[kVolumeSlots], tau[kVolumeSlots], radiance[kVolumeSlots];
  };
  std::vector<VolumeParts> volume_parts_;
  std::vector<PixelVolumeComponents> volume_components_;
  // With Settings::volume_beams, the same for beams: per pixel their photon statistics (r2 their
  // radius squared), per band pixel what the band's beams found, and their flux by slot.
  bool beams_ = false;
  std::vector<FloatPhotonStats> beam_pixels_;
  std::vector<VolumeFound> beam_band_;
  std::vector<VolumeParts> beam_parts_;
  std::vector<PixelVolumeComponents> beam_components_;
  void clear_band(std::vector<VolumeFound>& found, std::vector<VolumeParts>& parts) const;
  HitPoints hit_points_;      // the band being made, reused: no pass allocates once sizes settle
  EyePassScratch eye_scratch_;
};

}  // namespace ppm
