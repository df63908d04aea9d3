// Fixed hit points (see fixed_hit_points.h).
#include "ppm/fixed_hit_points.h"

#include "ppm/direct_light.h"
#include "ppm/parallel.h"
#include "ppm/progressive.h"
#include "ppm/scoped_seconds.h"

namespace ppm {

bool FixedHitPoints::prepare(const Poll& poll) {
  double seconds = 0.0;
  {
    ScopedSeconds timer(seconds);
    EyePassScratch scratch;  // freed once the hit points are made
    if (!eye_pass(*c_.scene, c_.settings, c_.eye_options(0, c_.settings.samples_per_pixel), hit_points_, scratch,
                  c_.cancel, poll))
      return false;
    if (!hit_points_.depth.empty()) c_.depth.swap(hit_points_.depth);
    if (!c_.measure_photon_spacing_once(hit_points_, poll)) return false;
  }
  c_.stats.eye_seconds = seconds;
  c_.stats.hit_points = hit_points_.size();
  widen_to_photon_spacing();
  report_empty_pixels();
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
  if (!c_.run_photon_pass(hit_points_, pass, poll, counters)) return false;
  stats.photon = counters;
  // Direct light adds its sums only when complete, so a cancel here keeps the image consistent.
  bool completed = true;
  if (c_.analysis.sample_direct && (c_.analysis.resample_direct || stats.direct_samples == 0)) {
    ScopedSeconds timer(stats.direct_seconds);
    completed = direct_light_pass(*c_.scene, c_.lights, c_.settings, pass, c_.threads, hit_points_, c_.direct_scratch,
                                  c_.cancel, poll);
    if (completed) ++stats.direct_samples;
  }
  {
    ScopedSeconds timer(stats.update_seconds);
    parallel_for(c_.threads, hit_points_.size(), [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i)
        progressive_update(hit_points_.points[i].r2, hit_points_.stats[i], c_.settings.alpha, c_.settings.threshold);
    });
  }
  ++stats.passes;
  return completed;
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

double FixedHitPoints::radius_mean() const {
  double sum = 0.0;
  for (const HitPoint& h : hit_points_.points) sum += std::sqrt(h.r2);
  return hit_points_.size() ? sum / hit_points_.size() : 0.0;
}

}  // namespace ppm
