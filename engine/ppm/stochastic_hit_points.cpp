// Stochastic hit points (see stochastic_hit_points.h).
#include "ppm/stochastic_hit_points.h"

#include "ppm/direct_light.h"
#include "ppm/parallel.h"
#include "ppm/progressive.h"
#include "ppm/scoped_seconds.h"

namespace ppm {

bool StochasticHitPoints::prepare(const Poll&) {
  const Camera& cam = c_.scene->camera();
  pixels_.assign(static_cast<size_t>(cam.width) * cam.height, PixelStats{});
  return true;
}

bool StochasticHitPoints::pass(const Poll& poll) {
  RenderStats& stats = c_.stats;
  const uint64_t pass = stats.passes;
  HitPoints& fresh = hit_points_;
  {
    ScopedSeconds timer(stats.eye_seconds);
    if (!eye_pass(*c_.scene, c_.settings, c_.eye_options(pass + 1, 1), fresh, c_.cancel, poll)) return false;
  }
  if (!c_.measure_photon_spacing_once(fresh, poll)) return false;
  start_at_pixel_radii(fresh);
  // Photons and direct light into the fresh hit points; a cancel drops the whole pass.
  PhotonPassCounters counters = stats.photon;
  c_.photon_pass.reset_index();
  if (!c_.run_photon_pass(fresh, pass, poll, counters)) return false;
  if (c_.analysis.sample_direct) {
    ScopedSeconds timer(stats.direct_seconds);
    if (!direct_light_pass(*c_.scene, c_.lights, c_.settings, pass, c_.threads, fresh, c_.direct_scratch, c_.cancel,
                           poll))
      return false;
  }
  {
    ScopedSeconds timer(stats.update_seconds);
    fold_into_pixels(fresh);
    if (!fresh.depth.empty()) c_.depth.swap(fresh.depth);
  }
  stats.photon = counters;
  if (c_.analysis.sample_direct) ++stats.direct_samples;
  stats.hit_points = fresh.size();
  ++stats.passes;
  return true;
}

// Every hit point gathers with its pixel's current radius; a pixel's first comes from its first
// hit point (no smaller than the photons' spacing, photon_density_radius.h).
void StochasticHitPoints::start_at_pixel_radii(HitPoints& fresh) {
  for (size_t p = 0; p < pixels_.size(); ++p)
    for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
      if (pixels_[p].r2 == 0.0) {
        pixels_[p].r2 = std::max(fresh.points[i].r2, c_.min_initial_r2);
        c_.stats.radii_widened += fresh.points[i].r2 < c_.min_initial_r2;
      }
      fresh.points[i].r2 = pixels_[p].r2;
    }
}

// The pass into the pixels: the same cross-generation rule as fixed hit points, per pixel.
void StochasticHitPoints::fold_into_pixels(const HitPoints& fresh) {
  parallel_for(c_.threads, pixels_.size(), [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      PixelStats& px = pixels_[p];
      for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
        px.stats.m += fresh.stats[i].m;
        px.stats.tau_m += fresh.stats[i].tau_m;
        px.stats.direct += fresh.stats[i].direct;
      }
      px.emitted += fresh.emitted[p];
      px.transparency += fresh.transparency[p];
      progressive_update(px.r2, px.stats, c_.settings.alpha, c_.settings.threshold);
    }
  });
}

PixelValue StochasticHitPoints::pixel(size_t p) const {
  const RenderStats& stats = c_.stats;
  const double direct_scale = stats.direct_samples > 0 ? 1.0 / stats.direct_samples : 0.0;
  const double pass_scale = stats.passes > 0 ? 1.0 / stats.passes : 0.0;
  const PixelStats& px = pixels_[p];
  Color c = px.emitted * pass_scale + px.stats.direct * direct_scale;
  c += c_.photon_radiance(px.r2, px.stats);
  return PixelValue{c, px.transparency * pass_scale};
}

double StochasticHitPoints::radius_mean() const {
  double sum = 0.0;
  size_t count = 0;
  for (const PixelStats& px : pixels_)
    if (px.r2 > 0.0) sum += std::sqrt(px.r2), ++count;
  return count ? sum / count : 0.0;
}

size_t StochasticHitPoints::memory_bytes() const {
  return pixels_.capacity() * sizeof(PixelStats) + hit_points_.memory_bytes();
}

}  // namespace ppm
