// The estimators the renderer can run, behind one interface: the render loop
// (renderer.cpp) is the same for all.
//   FixedHitPoints (fixed_hit_points.h): progressive photon mapping (Hachisuka
//     et al. 2008), one eye pass, statistics kept per hit point;
//   StreamedHitPoints (streamed_hit_points.h): the same fixed hit points made
//     again band by band each pass, where keeping them would not fit in memory;
//   StochasticHitPoints (stochastic_hit_points.h): stochastic PPM (Hachisuka &
//     Jensen 2009), new eye samples every pass, statistics kept per pixel.
#pragma once

#include "ppm/error_estimate.h"
#include "ppm/render_context.h"

#include <memory>

namespace ppm {

struct PixelValue {
  Color radiance;       // premultiplied by 1 - transparency, as Blender expects
  double transparency;  // the share of the pixel's eye samples that leave it transparent
};

class Estimator {
 public:
  virtual ~Estimator() = default;
  // Before the first pass (fixed: the eye pass). False if cancelled; then called again.
  virtual bool prepare(const Poll& poll) = 0;
  // One pass: photons, direct light, the progressive update. False if cancelled.
  virtual bool pass(const Poll& poll) = 0;
  // Pixel p (row 0 at the bottom) after the passes so far; only once prepared.
  virtual PixelValue pixel(size_t p) const = 0;
  // With settings.light_passes: what pixel p's camera rays see at no bounce (Cycles' Emit, Env).
  virtual SeenLight seen(size_t p) const = 0;
  // With settings.component_passes: pixel p's light by component (light_components.h); where
  // has_components() (streamed hit points keep none).
  virtual ComponentLight components(size_t) const { return ComponentLight{}; }
  virtual bool has_components() const { return false; }
  virtual double radius_mean() const = 0;
  // The share of the pass in progress already folded into the image (stochastic: its bands).
  virtual double pass_done() const { return 0.0; }
  virtual void add_memory(MemoryUse& use) const = 0;
  // Each pixel's pass values for the error estimate (error_estimate.h), row 0 at the bottom; a
  // pass adds to a pixel once it is folded into the image.
  const std::vector<PixelErrorStats>& errors() const { return errors_; }
  // How many passes they hold, pixel by pixel.
  virtual ErrorPasses error_passes() const = 0;
  // Per pixel, the variance of the mean of its fixed eye samples (error_estimate.h's anti-aliasing);
  // empty where the eye samples change every pass or are not kept.
  virtual const std::vector<float>& sampling_variance() const { return no_sampling_variance_; }

 protected:
  std::vector<PixelErrorStats> errors_;

 private:
  std::vector<float> no_sampling_variance_;
};

// The estimator `context.settings.hit_points` and `hit_point_storage` name; `context` must outlive it.
std::unique_ptr<Estimator> make_estimator(RenderContext& context);

}  // namespace ppm
