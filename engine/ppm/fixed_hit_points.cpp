// Fixed hit points (see fixed_hit_points.h).
#include "ppm/fixed_hit_points.h"

#include "ppm/direct_light.h"
#include "base/memory_budget.h"
#include "base/parallel.h"
#include "ppm/progressive.h"
#include "base/scoped_seconds.h"

#include <algorithm>
#include <string>

namespace ppm {

// Per eye sample a hit point (the eye pass frees its chunks as it joins them: EyePassOptions::
// release_chunks), its statistics and a pass's sums, and the light it saw directly; per pixel the
// pixel's records, the image read back and the error estimate's.
double kept_hit_point_bytes(const Camera& camera, int samples_per_pixel, bool components) {
  const double pixels = static_cast<double>(camera.width) * camera.height;
  const double per_sample = sizeof(HitPoint) + sizeof(HitPointShading) + sizeof(HitPointStats) +
                            sizeof(uint32_t) + 2 * sizeof(Color) + sizeof(Bounces) + sizeof(uint16_t) + sizeof(float) +
                            (components ? 2.0 + sizeof(HitPointComponents) + sizeof(ClassColors) + 4 * sizeof(Vec3f)
                                        : 0.0);
  const double per_pixel = 2 * sizeof(uint32_t) + sizeof(Color) + sizeof(double) + 5 * sizeof(float) +
                           sizeof(PixelErrorStats) + (components ? sizeof(ComponentLight) : 0);
  return pixels * (per_sample * samples_per_pixel + per_pixel);
}

void FixedHitPoints::check_memory_for_hit_points() const {
  const Camera& cam = c_.scene->camera();
  const double needed = kept_hit_point_bytes(cam, c_.settings.samples_per_pixel, c_.settings.component_passes);
  check_memory(static_cast<size_t>(std::min(needed, 1e18)),
               "fixed hit points at " + std::to_string(cam.width) + "x" + std::to_string(cam.height) + " and " +
                   std::to_string(c_.settings.samples_per_pixel) + " samples per pixel",
               "use stochastic hit points (52 bytes a pixel) or fewer samples per pixel");
}

bool FixedHitPoints::prepare(const Poll& poll) {
  check_memory_for_hit_points();
  double seconds = 0.0;
  {
    ScopedSeconds timer(seconds);
    EyePassScratch scratch;  // freed once the hit points are made
    EyePassOptions eye = c_.eye_options(0, c_.settings.samples_per_pixel);
    eye.record_samples = c_.settings.samples_per_pixel > 1;  // the error estimate's anti-aliasing term
    eye.record_seen = c_.settings.light_passes;
    eye.record_components = c_.settings.component_passes;
    eye.release_chunks = true;
    if (!eye_pass(*c_.scene, c_.settings, eye, hit_points_, scratch, c_.cancel, poll)) return false;
    if (!hit_points_.depth.empty()) c_.depth.swap(hit_points_.depth);
    if (!c_.measure_photon_spacing_once(hit_points_, poll)) return false;
  }
  c_.stats.eye_seconds = seconds;
  c_.stats.hit_points = hit_points_.size();
  widen_to_photon_spacing();
  report_empty_pixels();
  errors_.assign(hit_points_.pixel_begin.size() - 1, PixelErrorStats{});
  return true;
}

// Automatic initial radii below the photons' spacing start at it (photon_density_radius.h).
void FixedHitPoints::widen_to_photon_spacing() {
  double sum = 0.0;
  for (HitPoint& h : hit_points_.points) {
    if (h.r2 < c_.min_initial_r2) h.r2 = c_.min_initial_r2, ++c_.stats.radii_widened;
    sum += std::sqrt(h.r2);
  }
  c_.stats.initial_radius_mean = hit_points_.size() ? sum / hit_points_.size() : 0.0;
}

void FixedHitPoints::report_empty_pixels() {
  const size_t pixels = static_cast<size_t>(c_.scene->camera().width) * c_.scene->camera().height;
  size_t empty = 0;
  for (size_t p = 0; p < pixels; ++p) empty += hit_points_.pixel_begin[p] == hit_points_.pixel_begin[p + 1];
  if (empty > 0)
    c_.stats.skipped.push_back("hit points: " + std::to_string(empty) +
                               " pixels see only background, emitters or nothing");
}

bool FixedHitPoints::pass(const Poll& poll) {
  RenderStats& stats = c_.stats;
  const uint64_t pass = stats.passes;
  // Photons first: a pass cancelled inside the photon pass leaves no trace.
  PhotonPassCounters counters = stats.photon;
  c_.weigh_pixels_for_guide(errors_, error_passes());
  if (!c_.run_photon_pass(hit_points_, pass, poll, counters)) return false;
  c_.learn_guide();
  stats.photon = counters;
  // Direct light adds its sums only when complete, so a cancel here keeps the image consistent.
  bool completed = true, direct_sampled = false;
  if (c_.analysis.sample_direct && (c_.analysis.resample_direct || stats.direct_samples == 0)) {
    ScopedSeconds timer(stats.direct_seconds);
    completed = direct_light_pass(*c_.scene, c_.lights, c_.settings, pass, c_.threads, hit_points_, c_.direct_scratch,
                                  c_.cancel, poll);
    if (completed) ++stats.direct_samples;
    direct_sampled = completed;
  }
  {
    ScopedSeconds timer(stats.update_seconds);
    update_pixels(direct_sampled);
  }
  ++stats.passes;
  return completed;
}

// Pixel by pixel, in one sweep over the hit points: the pixel's value from this pass alone and its
// bias estimate go to the error estimate (error_estimate.h), at the radii the photons were gathered
// with (what its eye paths see, this pass's direct sample or the mean where direct light is sampled
// once, the pass's photons); then each hit point's progressive update.
void FixedHitPoints::update_pixels(bool direct_sampled) {
  const double direct_scale = c_.stats.direct_samples > 0 ? 1.0 / c_.stats.direct_samples : 0.0;
  const double photons = static_cast<double>(c_.settings.photons_per_pass);
  const double alpha = c_.settings.alpha;
  const uint32_t threshold = c_.settings.threshold;
  parallel_for(c_.threads, errors_.size(), [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      double value = luminance(hit_points_.emitted[p]), bias = 0.0;
      for (uint32_t i = hit_points_.pixel_begin[p]; i < hit_points_.pixel_begin[p + 1]; ++i) {
        HitPointStats& s = hit_points_.stats[i];
        double& r2 = hit_points_.points[i].r2;
        value += direct_sampled ? luminance(c_.direct_scratch.sums[i]) : luminance(s.direct) * direct_scale;
        const double scale = c_.pass_radiance_scale(r2, photons);
        value += scale * s.pass_flux;
        bias += scale * s.pass_bias;
        const double ratio = progressive_update(r2, s, alpha, threshold);
        if (!hit_points_.components.empty()) hit_points_.components[i].fold(ratio);
      }
      errors_[p].add(value, bias, c_.stats.passes + 1);
    }
  });
}

// The spread of each pixel's eye samples (error_estimate.h): sample s's value is what it saw
// directly plus its hit points' current estimates, times the samples per pixel (each carries 1/spp).
const std::vector<float>& FixedHitPoints::sampling_variance() const {
  const int spp = c_.settings.samples_per_pixel;
  if (hit_points_.sample_light.empty() || c_.stats.passes == 0) {
    sampling_variance_.clear();
    return sampling_variance_;
  }
  if (sampling_variance_passes_ == c_.stats.passes && !sampling_variance_.empty()) return sampling_variance_;
  const double direct_scale = c_.stats.direct_samples > 0 ? 1.0 / c_.stats.direct_samples : 0.0;
  const double photons_emitted = static_cast<double>(c_.stats.photon.emitted);
  const size_t pixels = hit_points_.pixel_begin.size() - 1;
  sampling_variance_.resize(pixels);
  parallel_for(c_.threads, pixels, [&](size_t begin, size_t end) {
    std::vector<double> value(spp);
    for (size_t p = begin; p < end; ++p) {
      for (int s = 0; s < spp; ++s) value[s] = hit_points_.sample_light[p * spp + s];
      for (uint32_t i = hit_points_.pixel_begin[p]; i < hit_points_.pixel_begin[p + 1]; ++i) {
        const HitPointStats& st = hit_points_.stats[i];
        value[st.sample] += luminance(st.direct) * direct_scale +
                            luminance(c_.photon_radiance(hit_points_.points[i].r2, st, photons_emitted));
      }
      double mean = 0.0, m2 = 0.0;
      for (int s = 0; s < spp; ++s) mean += value[s] * spp;
      mean /= spp;
      for (int s = 0; s < spp; ++s) m2 += (value[s] * spp - mean) * (value[s] * spp - mean);
      sampling_variance_[p] = static_cast<float>(m2 / ((spp - 1.0) * spp));
    }
  });
  sampling_variance_passes_ = c_.stats.passes;
  return sampling_variance_;
}

PixelValue FixedHitPoints::pixel(size_t p) const {
  const double direct_scale = c_.stats.direct_samples > 0 ? 1.0 / c_.stats.direct_samples : 0.0;
  const double photons_emitted = static_cast<double>(c_.stats.photon.emitted);
  Color c = hit_points_.emitted[p];
  for (uint32_t i = hit_points_.pixel_begin[p]; i < hit_points_.pixel_begin[p + 1]; ++i) {
    const HitPointStats& s = hit_points_.stats[i];
    c += s.direct * direct_scale;
    c += c_.photon_radiance(hit_points_.points[i].r2, s, photons_emitted);
  }
  return PixelValue{c, hit_points_.transparency[p]};
}

ComponentLight FixedHitPoints::components(size_t p) const {
  if (hit_points_.pixel_components.empty()) return ComponentLight{};
  const double direct_scale = c_.stats.direct_samples > 0 ? 1.0 / c_.stats.direct_samples : 0.0;
  const double photons_emitted = static_cast<double>(c_.stats.photon.emitted);
  ComponentLight out = hit_points_.pixel_components[p];
  for (uint32_t i = hit_points_.pixel_begin[p]; i < hit_points_.pixel_begin[p + 1]; ++i)
    hit_points_.components[i].add_to(out, hit_points_.route[i], direct_scale,
                                      c_.pass_radiance_scale(hit_points_.points[i].r2, photons_emitted));
  return out;
}

double FixedHitPoints::radius_mean() const {
  double sum = 0.0;
  for (const HitPoint& h : hit_points_.points) sum += std::sqrt(h.r2);
  return hit_points_.size() ? sum / hit_points_.size() : 0.0;
}

}  // namespace ppm
