// What the two estimators (fixed_hit_points.h, stochastic_hit_points.h) share
// of a render: the scene and settings and what is derived from them once, the
// pass machinery, and the statistics they report.
#pragma once

#include "ppm/direct_light.h"
#include "ppm/error_estimate.h"
#include "ppm/eye_pass.h"
#include "ppm/photon_pass.h"
#include "ppm/render_stats.h"
#include "ppm/scene_analysis.h"
#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

namespace ppm {

using Poll = std::function<bool()>;  // false: cancel (what becomes of the pass in progress: renderer.h)

struct RenderContext {
  RenderContext(std::shared_ptr<const Scene> scene, const Settings& settings);

  // The options of an eye pass with `samples_per_pixel`; `generation` numbers its random samples.
  EyePassOptions eye_options(uint64_t generation, int samples_per_pixel) const;
  // The photons' spacing, once per render, before any initial radius is set (automatic radii
  // only): `min_initial_r2` is then its square, `min_volume_r2` the volume photons'. False if
  // cancelled.
  bool measure_photon_spacing_once(const HitPoints& hp, const Poll& poll);
  // The same from the hit points' mean radius (0: there are none).
  bool measure_photon_spacing_once(double mean_radius, const Poll& poll);
  // One pass's photons into the hit points' pending statistics, counted in `counters` (a copy
  // the caller keeps once the pass completes). With nothing to trace, only their number.
  bool run_photon_pass(HitPoints& hp, uint64_t pass, const Poll& poll, PhotonPassCounters& counters);
  // Hit points made band by band (stochastic, and streamed fixed ones): rows of about kBandPixels
  // eye samples. The hit-point-indexed gather needs every hit point before the photons fly: the
  // image is then one band.
  static constexpr size_t kBandPixels = size_t(1) << 16;
  int band_rows(int samples_per_pixel = 1) const;
  // Calls `band` for the bands of `rows` rows from `next_row` to the image's top, setting `eye`'s
  // rows and moving `next_row` past each band done. Between bands it stops where the run asked to
  // pause (`paused`). True once the last band is done; false if a band was cancelled or it paused.
  bool run_bands(int& next_row, int rows, EyePassOptions& eye,
                 const std::function<bool(const EyePassOptions&)>& band);
  // The pass's photons into one band's pending statistics: traced and indexed at the first band
  // (`typical_r2`, a hit point's radius^2, sizes the hashed grid's cells), then gathered band by
  // band. False if cancelled.
  bool gather_band(HitPoints& band, bool first_band, uint64_t pass, double typical_r2, const Poll& poll,
                   PhotonPassCounters& counters);
  // Radiance of the photons gathered at radius^2 `r2` into `s`, over `photons_emitted`.
  Color photon_radiance(double r2, const HitPointStats& s, double photons_emitted) const;
  // What turns a hit point's pass_flux and pass_bias (gathered at radius^2 `r2` from one pass of
  // `photons` photons) into radiance: the error estimate's pass values (error_estimate.h).
  double pass_radiance_scale(double r2, double photons) const {
    if (!analysis.trace_photons || !(r2 > 0.0) || !(photons > 0.0)) return 0.0;
    return lights.flux_unit() / (kPi * r2 * photons);
  }
  // The same for a hit point in a medium, its photons' flux (sigma_s included, progressive.h)
  // gathered in a sphere of radius^2 `r2`: one pass's volume estimate per unit of flux.
  double volume_radiance_scale(double r2, double photons) const {
    if (!analysis.trace_photons || !(r2 > 0.0) || !(photons > 0.0)) return 0.0;
    return lights.flux_unit() / (4.0 / 3.0 * kPi * r2 * std::sqrt(r2) * photons);
  }
  // The same for an eye beam, its photon beams' crossings weighed by the 1-D kernel of half-width r
  // (Beam x Beam 1D, photon_pass_beams.cpp).
  double beam_radiance_scale(double r2, double photons) const {
    if (!analysis.trace_photons || !(r2 > 0.0) || !(photons > 0.0)) return 0.0;
    return lights.flux_unit() / (2.0 * std::sqrt(r2) * photons);
  }
  void add_memory(MemoryUse& use) const;
  // Photon guiding (photon_guide.h), at the start of a pass: each pixel's weight from the error
  // estimate so far (its noise over its luminance, no credit before kMinErrorPasses). Then at the
  // pass's end: learn_guide() folds the pass's credits into the guide.
  void weigh_pixels_for_guide(const std::vector<PixelErrorStats>& errors, const ErrorPasses& passes);
  void learn_guide() {
    if (settings.photon_guiding) photon_pass.learn_guide();
  }

  std::shared_ptr<const Scene> scene;
  Settings settings;
  Scene::Lease lease;  // the scene refuses changes while this render lives
  int threads;
  LightSampler lights;
  SceneAnalysis analysis;
  PhotonPass photon_pass;
  DirectScratch direct_scratch;  // direct_light_pass's sums, kept so that no pass allocates
  bool dof_post = false, dof_lens = false;
  std::vector<float> depth;  // per pixel, bottom row first like the eye pass (POST depth of field)
  std::vector<float> guide_weights;  // per pixel, with photon guiding
  double min_initial_r2 = 0.0;  // floor for automatic initial radii (photon_density_radius.h)
  double min_volume_r2 = 0.0;   // the same in media
  bool spacing_measured = false;
  std::atomic<bool> cancel{false};
  // Between two bands of a stochastic pass, whether the run asked to pause there (the next run
  // continues the pass); `paused` then says it did.
  std::function<bool()> pause_due;
  bool paused = false;
  RenderStats stats;

 private:
  void decide_depth_of_field();
};

}  // namespace ppm
