// Fixed hit points, streamed (see streamed_hit_points.h).
#include "ppm/streamed_hit_points.h"

#include "ppm/direct_light.h"
#include "base/memory_budget.h"
#include "base/parallel.h"
#include "base/scoped_seconds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ppm {

// The records kept for `hit_points` hit points, the per-pixel arrays, a depth buffer and the image
// read back; one band's hit points come on top, a few tens of MB whatever the image.
void StreamedHitPoints::check_memory_for(double hit_points) const {
  const Camera& cam = c_.scene->camera();
  const double pixels = static_cast<double>(cam.width) * cam.height;
  const double needed = hit_points * sizeof(FloatPhotonStats) +
                        pixels * (sizeof(uint32_t) + sizeof(Vec3f) + sizeof(PixelErrorStats) + 2 * sizeof(float) +
                                  4 * sizeof(float));
  check_memory(static_cast<size_t>(std::min(needed, 1e18)),
               "fixed hit points at " + std::to_string(cam.width) + "x" + std::to_string(cam.height) + " and " +
                   std::to_string(c_.settings.samples_per_pixel) + " samples per pixel, streamed,",
               "use stochastic hit points (52 bytes a pixel) or fewer samples per pixel");
}

bool StreamedHitPoints::prepare(const Poll& poll) {
  const Camera& cam = c_.scene->camera();
  const size_t pixels = static_cast<size_t>(cam.width) * cam.height;
  check_memory_for(static_cast<double>(pixels) * c_.settings.samples_per_pixel);  // about one per eye sample
  double seconds = 0.0, mean_radius = 0.0;
  {
    ScopedSeconds timer(seconds);
    if (!count_hit_points(poll, mean_radius)) return false;
  }
  c_.stats.eye_seconds += seconds;
  if (!c_.measure_photon_spacing_once(mean_radius, poll)) return false;
  const size_t total = first_.back();
  check_memory_for(static_cast<double>(total));
  stats_.resize(total);
  parallel_for(c_.threads, total, [&](size_t begin, size_t end) {
    std::fill(stats_.begin() + begin, stats_.begin() + end, FloatPhotonStats{});
  });
  c_.stats.hit_points = total;
  size_t empty = 0;
  for (size_t p = 0; p < pixels; ++p) empty += first_[p] == first_[p + 1];
  if (empty > 0)
    c_.stats.skipped.push_back("hit points: " + std::to_string(empty) +
                               " pixels see only background, emitters or nothing");
  return true;
}

// The first eye pass, band by band: how many hit points each pixel has, what its eye paths see
// directly, and their mean radius (for the photons' spacing). False if cancelled.
bool StreamedHitPoints::count_hit_points(const Poll& poll, double& mean_radius) {
  const Camera& cam = c_.scene->camera();
  const size_t pixels = static_cast<size_t>(cam.width) * cam.height;
  first_.assign(pixels + 1, 0);
  light_.assign(pixels, Vec3f(0.0f));
  transparency_.assign(pixels, 0.0f);
  errors_.assign(pixels, PixelErrorStats{});
  EyePassOptions eye = c_.eye_options(0, c_.settings.samples_per_pixel);
  eye.record_seen = c_.settings.light_passes;
  seen_.assign(eye.record_seen ? pixels : 0, SeenLight{});
  std::vector<float> depth;
  if (eye.record_depth) depth.assign(pixels, std::numeric_limits<float>::infinity());
  uint64_t total = 0;
  double radius_sum = 0.0;
  const int rows = c_.band_rows(c_.settings.samples_per_pixel);
  for (int row = 0; row < cam.height; row += rows) {
    eye.row_begin = row;
    eye.row_end = std::min(cam.height, row + rows);
    HitPoints& fresh = hit_points_;
    if (!eye_pass(*c_.scene, c_.settings, eye, fresh, eye_scratch_, c_.cancel, poll)) return false;
    const size_t first_pixel = static_cast<size_t>(row) * cam.width;
    for (size_t p = 0; p + 1 < fresh.pixel_begin.size(); ++p) {
      total += fresh.pixel_begin[p + 1] - fresh.pixel_begin[p];
      if (total > std::numeric_limits<uint32_t>::max())
        throw MemoryShortage("fixed hit points: more than 2^32 of them at " + std::to_string(cam.width) + "x" +
                             std::to_string(cam.height) + "; use stochastic hit points or fewer samples per pixel");
      first_[first_pixel + p + 1] = static_cast<uint32_t>(total);
      light_[first_pixel + p] = Vec3f(fresh.emitted[p]);
      transparency_[first_pixel + p] = static_cast<float>(fresh.transparency[p]);
      if (eye.record_seen) seen_[first_pixel + p] = fresh.seen[p];
    }
    for (const HitPoint& h : fresh.points) radius_sum += std::sqrt(h.r2);
    if (eye.record_depth) std::copy(fresh.depth.begin(), fresh.depth.end(), depth.begin() + first_pixel);
  }
  if (eye.record_depth) c_.depth.swap(depth);
  mean_radius = total ? radius_sum / total : 0.0;
  return true;
}

bool StreamedHitPoints::pass(const Poll& poll) {
  RenderStats& stats = c_.stats;
  const uint64_t pass = stats.passes;
  const int spp = c_.settings.samples_per_pixel;
  EyePassOptions eye = c_.eye_options(0, spp);  // generation 0: the same samples
  if (current_.next_row == 0) current_ = PassInProgress{0, stats.photon, 0.0};
  if (!c_.run_bands(current_.next_row, c_.band_rows(spp), eye,
                    [&](const EyePassOptions& e) { return band(e, pass, poll); }))
    return false;
  stats.photon = current_.counters;
  if (direct_light_due()) ++stats.direct_samples;
  if (pass == 0) stats.initial_radius_mean = stats_.empty() ? 0.0 : initial_radius_sum_ / stats_.size();
  typical_r2_ = stats_.empty() ? 0.0 : current_.sum_r2 / stats_.size();
  ++stats.passes;
  current_.next_row = 0;
  return true;
}

bool StreamedHitPoints::band(const EyePassOptions& eye, uint64_t pass, const Poll& poll) {
  RenderStats& stats = c_.stats;
  HitPoints& fresh = hit_points_;
  {
    ScopedSeconds timer(stats.eye_seconds);
    if (!eye_pass(*c_.scene, c_.settings, eye, fresh, eye_scratch_, c_.cancel, poll)) return false;
  }
  const size_t first_pixel = static_cast<size_t>(eye.row_begin) * c_.scene->camera().width;
  const size_t last_pixel = first_pixel + fresh.pixel_begin.size() - 1;
  const size_t first = first_[first_pixel];
  if (fresh.size() != first_[last_pixel] - first)  // the eye pass is deterministic: a bug if this fails
    throw std::logic_error("streamed hit points: rows " + std::to_string(eye.row_begin) + "-" +
                           std::to_string(eye.row_end) + " made " + std::to_string(fresh.size()) +
                           " hit points, the first eye pass " + std::to_string(first_[last_pixel] - first));
  start_at_kept_radii(first);
  const bool first_band = eye.row_begin == 0;
  const double typical_r2 = pass == 0 && first_band ? mean_r2_of_band() : typical_r2_;
  if (!c_.gather_band(fresh, first_band, pass, typical_r2, poll, current_.counters)) return false;
  if (direct_light_due()) {
    ScopedSeconds timer(stats.direct_seconds);
    if (!direct_light_pass(*c_.scene, c_.lights, c_.settings, pass, c_.threads, fresh, c_.direct_scratch, c_.cancel,
                           poll, first))
      return false;
  }
  {  // not polled: a band is folded whole or not at all
    ScopedSeconds timer(stats.update_seconds);
    fold_band(first_pixel);
  }
  return true;
}

// Every hit point gathers with its kept radius; at its first pass that is the eye pass's radius,
// no smaller than the photons' spacing (photon_density_radius.h).
void StreamedHitPoints::start_at_kept_radii(size_t first) {
  HitPoints& fresh = hit_points_;
  for (size_t i = 0; i < fresh.size(); ++i) {
    FloatPhotonStats& s = stats_[first + i];
    if (s.r2 == 0.0f) {
      const double r2 = std::max(fresh.points[i].r2, c_.min_initial_r2);
      c_.stats.radii_widened += fresh.points[i].r2 < c_.min_initial_r2;
      s.r2 = static_cast<float>(r2);
      initial_radius_sum_ += std::sqrt(static_cast<double>(s.r2));
    }
    fresh.points[i].r2 = s.r2;
  }
}

double StreamedHitPoints::mean_r2_of_band() const {
  double sum = 0.0;
  for (const HitPoint& h : hit_points_.points) sum += h.r2;
  return hit_points_.size() ? sum / hit_points_.size() : 0.0;
}

// Sampled every pass, or once when every light is a delta light (the sample is then exact).
bool StreamedHitPoints::direct_light_due() const {
  return c_.analysis.sample_direct && (c_.analysis.resample_direct || c_.stats.direct_samples == 0);
}

// The band's photons into its hit points' records, with the progressive update; its direct light,
// which adds up per pixel, into the pixels' running means (seen directly plus direct light).
void StreamedHitPoints::fold_band(size_t first_pixel) {
  const HitPoints& fresh = hit_points_;
  const size_t band_pixels = fresh.pixel_begin.size() - 1, first = first_[first_pixel];
  const bool direct = direct_light_due();
  const float w = 1.0f / static_cast<float>(c_.stats.direct_samples + 1);
  const double alpha = c_.settings.alpha;
  const uint32_t threshold = c_.settings.threshold;
  const double photons = static_cast<double>(current_.counters.emitted - c_.stats.photon.emitted);
  constexpr size_t kBlock = 4096;  // pixels; sums of r^2 by block: the same whichever thread folds which
  const size_t blocks = (band_pixels + kBlock - 1) / kBlock;
  block_sums_.assign(blocks, 0.0);
  parallel_each(c_.threads, blocks, [&](size_t b) {
    double sum_r2 = 0.0;
    for (size_t p = b * kBlock; p < std::min(band_pixels, (b + 1) * kBlock); ++p) {
      Color light = fresh.emitted[p];
      double photon_value = 0.0, bias = 0.0;  // this pass's, for the error estimate (error_estimate.h)
      for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
        const HitPointStats& found = fresh.stats[i];
        FloatPhotonStats& s = stats_[first + i];
        const double scale = c_.pass_radiance_scale(s.r2, photons);  // the radius it gathered with
        photon_value += scale * found.pass_flux;
        bias += scale * found.pass_bias;
        s.fold(found.m, Vec3f(found.tau_m), alpha, threshold);
        sum_r2 += s.r2;
        light += found.direct;
      }
      Vec3f& mean = light_[first_pixel + p];
      if (direct) mean += (Vec3f(light) - mean) * w;
      errors_[first_pixel + p].add(luminance(direct ? light : Color(mean)) + photon_value, bias, c_.stats.passes + 1);
    }
    block_sums_[b] = sum_r2;
  });
  for (double sum : block_sums_) current_.sum_r2 += sum;
}

PixelValue StreamedHitPoints::pixel(size_t p) const {
  // The rows a cancelled pass completed have its photons too.
  const bool in_pass = p < static_cast<size_t>(current_.next_row) * c_.scene->camera().width;
  const double emitted = static_cast<double>(in_pass ? current_.counters.emitted : c_.stats.photon.emitted);
  Color c(light_[p]);
  for (uint32_t i = first_[p]; i < first_[p + 1]; ++i)
    c += c_.photon_radiance(stats_[i].r2, stats_[i].in_double(), emitted);
  return PixelValue{c, transparency_[p]};
}

double StreamedHitPoints::pass_done() const {
  return static_cast<double>(current_.next_row) / c_.scene->camera().height;
}

double StreamedHitPoints::radius_mean() const {
  double sum = 0.0;
  for (const FloatPhotonStats& s : stats_) sum += std::sqrt(static_cast<double>(s.r2));
  return stats_.empty() ? 0.0 : sum / stats_.size();
}

void StreamedHitPoints::add_memory(MemoryUse& use) const {
  use.hit_points += stats_.capacity() * sizeof(FloatPhotonStats) + hit_points_.memory_bytes() +
                    eye_scratch_.memory_bytes();
  use.pixels += first_.capacity() * sizeof(uint32_t) + light_.capacity() * sizeof(Vec3f) +
                transparency_.capacity() * sizeof(float) + errors_.capacity() * sizeof(PixelErrorStats);
}

}  // namespace ppm
