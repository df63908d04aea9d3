// Stochastic hit points (see stochastic_hit_points.h).
#include "ppm/stochastic_hit_points.h"

#include "ppm/adaptive_samples.h"
#include "ppm/direct_light.h"
#include "base/memory_budget.h"
#include "base/parallel.h"
#include "ppm/radius_schedule.h"
#include "base/scoped_seconds.h"

#include <algorithm>
#include <limits>
#include <string>

namespace ppm {

bool StochasticHitPoints::prepare(const Poll&) {
  const Camera& cam = c_.scene->camera();
  // The pixels' statistics, a depth buffer and the image read back, before any of it is made; the
  // light passes' and adaptive sampling's where asked for.
  const double pixels = static_cast<double>(cam.width) * cam.height;
  media_ = c_.scene->has_media();
  // The global schedule keeps no volume statistics: the pass's volume radiance joins its mean.
  const bool volume_stats = media_ && c_.settings.radius_schedule != RadiusSchedule::Global;
  const bool volume_components = volume_stats && c_.settings.component_passes;
  beams_ = media_ && c_.settings.volume_beams;
  const int volume_sets = volume_stats ? 1 + beams_ : 0;  // hit points' and beams'
  const size_t optional = (c_.settings.light_passes ? sizeof(SeenMeans) : 0) + (c_.settings.adaptive_samples > 1) +
                          (c_.settings.component_passes ? sizeof(PixelComponents) : 0) +
                          volume_sets * sizeof(FloatPhotonStats) +
                          (volume_components ? volume_sets * sizeof(PixelVolumeComponents) : 0);
  check_memory(static_cast<size_t>(pixels * (sizeof(PixelStats) + sizeof(PixelErrorStats) + 2 * sizeof(float) +
                                              4 * sizeof(float) + optional)),
               "stochastic hit points at " + std::to_string(cam.width) + "x" + std::to_string(cam.height),
               "render a smaller image or in parts (render border)");
  pixels_.assign(static_cast<size_t>(cam.width) * cam.height, PixelStats{});
  errors_.assign(pixels_.size(), PixelErrorStats{});
  seen_.assign(c_.settings.light_passes ? pixels_.size() : 0, SeenMeans{Vec3f(0.0f), Vec3f(0.0f)});
  components_.assign(c_.settings.component_passes ? pixels_.size() : 0, PixelComponents{});
  volume_pixels_.assign(volume_stats ? pixels_.size() : 0, FloatPhotonStats{});
  volume_components_.assign(volume_components ? pixels_.size() : 0, PixelVolumeComponents{});
  beam_pixels_.assign(volume_stats && beams_ ? pixels_.size() : 0, FloatPhotonStats{});
  beam_components_.assign(volume_components && beams_ ? pixels_.size() : 0, PixelVolumeComponents{});
  current_ = PassInProgress{};
  return true;
}

bool StochasticHitPoints::pass(const Poll& poll) {
  RenderStats& stats = c_.stats;
  const uint64_t pass = stats.passes;  // this renderer's count; index(pass) is the still's
  // Adaptive eye sampling (adaptive_samples.h) once the error estimate has passes enough to go on.
  const int max_samples = c_.settings.adaptive_samples;
  const bool adaptive = max_samples > 1 && pass >= static_cast<uint64_t>(c_.settings.error_min_passes);
  EyePassOptions eye = c_.eye_options(index(pass) + 1, adaptive ? max_samples : 1);
  eye.record_seen = c_.settings.light_passes;
  eye.record_components = c_.settings.component_passes;
  if (current_.next_row == 0) {
    current_ = PassInProgress{0, stats.photon, 0};
    if (eye.record_depth) depth_.assign(pixels_.size(), std::numeric_limits<float>::infinity());
    if (adaptive) allocate_eye_samples(errors_, pass, max_samples, eye_samples_);
    c_.weigh_pixels_for_guide(errors_, error_passes());
  }
  if (adaptive) eye.pixel_samples = eye_samples_.data();
  if (!c_.run_bands(current_.next_row, c_.band_rows(adaptive ? max_samples : 1), eye,
                    [&](const EyePassOptions& e) { return band(e, pass, poll); }))
    return false;
  if (eye.record_depth) c_.depth.swap(depth_);
  c_.learn_guide();
  stats.photon = current_.counters;
  if (c_.analysis.sample_direct) ++stats.direct_samples;
  stats.hit_points = current_.hit_points;
  ++stats.passes;
  current_.next_row = 0;
  return true;
}

bool StochasticHitPoints::band(const EyePassOptions& eye, uint64_t pass, const Poll& poll) {
  RenderStats& stats = c_.stats;
  HitPoints& fresh = hit_points_;
  {
    ScopedSeconds timer(stats.eye_seconds);
    if (!eye_pass(*c_.scene, c_.settings, eye, fresh, eye_scratch_, c_.cancel, poll)) return false;
  }
  const size_t first_pixel = static_cast<size_t>(eye.row_begin) * c_.scene->camera().width;
  const bool first_band = eye.row_begin == 0;
  if (first_band && !c_.measure_photon_spacing_once(fresh, poll)) return false;
  const bool global = c_.settings.radius_schedule == RadiusSchedule::Global;
  if (global)
    start_at_global_radii(first_pixel, index(pass) + 1);
  else
    start_at_pixel_radii(first_pixel);
  if (!gather_photons(first_band, index(pass), poll)) return false;
  if (c_.analysis.sample_direct) {
    ScopedSeconds timer(stats.direct_seconds);
    if (!direct_light_pass(*c_.scene, c_.lights, c_.settings, index(pass), c_.threads, fresh, c_.direct_scratch,
                           c_.cancel, poll, current_.hit_points))
      return false;
  }
  if (beams_) start_beams(index(pass));
  if (media_ && !volume_band(first_pixel, index(pass), eye.pixel_samples, poll)) return false;
  if (beams_ && !beam_band(first_pixel, eye.pixel_samples, poll)) return false;
  {  // not polled: a band is folded whole or not at all
    ScopedSeconds timer(stats.update_seconds);
    if (global)
      fold_band_global(first_pixel, pass + 1);
    else
      fold_band(first_pixel, pass + 1, eye.pixel_samples);
    if (eye.record_depth) std::copy(fresh.depth.begin(), fresh.depth.end(), depth_.begin() + first_pixel);
  }
  c_.photon_pass.keep_band_credit();
  current_.hit_points += fresh.size() + fresh.volume.size();
  return true;
}

// The pass's photons into the band's hit points; the first band's mean radius sizes a hashed grid.
bool StochasticHitPoints::gather_photons(bool first_band, uint64_t pass, const Poll& poll) {
  double sum_r2 = 0.0;
  if (first_band)
    for (const HitPoint& h : hit_points_.points) sum_r2 += h.r2;
  const double typical_r2 = hit_points_.size() ? sum_r2 / hit_points_.size() : 0.0;
  return c_.gather_band(hit_points_, first_band, pass, typical_r2, poll, current_.counters);
}

// The band's hit points in media: gathered and lit (polled), then, with nothing polled left in the
// band, summed per band pixel (volume_band_); with the progressive radii their photons are folded
// into their pixels' volume statistics (the 3-D rule), with the global schedule their radiance
// joins the pass's value in fold_band_global. Their direct light is added to what the pixel's eye
// paths saw (`emitted`, folded with the rest by fold_band).
bool StochasticHitPoints::volume_band(size_t first_pixel, uint64_t pass, const uint8_t* pixel_samples,
                                      const Poll& poll) {
  std::vector<VolumeHitPoint>& points = hit_points_.volume;
  const bool global = c_.settings.radius_schedule == RadiusSchedule::Global;
  if (global)
    start_volume_at_global_radii(pass + 1);
  else
    for (VolumeHitPoint& h : points) {  // its own initial radius, shrunk as its pixel's have been
      FloatPhotonStats& px = volume_pixels_[h.pixel];
      if (px.r2 == 0.0f) px.r2 = 1.0f;
      h.r2 = static_cast<float>(std::max<double>(h.r2, c_.min_volume_r2) * px.r2);
    }
  if (c_.analysis.trace_photons && !c_.photon_pass.gather_volume(*c_.scene, points, c_.cancel, poll, current_.counters))
    return false;
  if (c_.analysis.sample_direct) {
    ScopedSeconds timer(c_.stats.direct_seconds);
    if (!volume_direct_light_pass(*c_.scene, c_.lights, c_.settings, pass, c_.threads, points, c_.cancel, poll,
                                  current_.hit_points))
      return false;
  }
  sum_volume_band(first_pixel);
  for (size_t p = 0; p < volume_band_.size(); ++p) {
    const VolumeFound& f = volume_band_[p];
    const uint32_t samples = pixel_samples ? pixel_samples[first_pixel + p] : 1;
    if (!global) {
      const double ratio = volume_pixels_[first_pixel + p].fold_volume((f.m + samples / 2) / samples, f.tau,
                                                                       c_.settings.alpha, c_.settings.threshold);
      if (!volume_components_.empty()) volume_components_[first_pixel + p].fold(volume_parts_[p].tau, ratio);
    }
    hit_points_.emitted[p] += Color(f.direct);
  }
  return true;
}

// Each beam at its pixel's beam radius (a pixel's first beam sets it, no smaller than the volume
// photons' spacing) or the global schedule's (a 1-D kernel's: r follows the surface's product); in
// a medium thin at that radius it gathers the photon beams and its segment's hit point skips their
// photons, else (r2 0) the hit point gathers them all.
void StochasticHitPoints::start_beams(uint64_t pass) {
  const bool global = c_.settings.radius_schedule == RadiusSchedule::Global;
  const double factor = global ? global_radius_factor_in(1, pass + 1, c_.settings.alpha) : 1.0;
  for (VolumeBeam& b : hit_points_.beams) {
    const double initial = std::max<double>(b.r2, c_.min_volume_r2);
    if (global) {
      b.r2 = static_cast<float>(initial * factor);
    } else {
      FloatPhotonStats& px = beam_pixels_[b.pixel];
      if (px.r2 == 0.0f) px.r2 = static_cast<float>(initial);
      b.r2 = px.r2;
    }
    if (max_component(Color(b.sigma_t)) * std::sqrt(static_cast<double>(b.r2)) > kThinBeam)
      b.r2 = 0.0f;
    else if (b.point != kNoPoint)
      hit_points_.volume[b.point].beamed_elsewhere = true;
  }
}

bool StochasticHitPoints::beam_band(size_t first_pixel, const uint8_t* pixel_samples, const Poll& poll) {
  std::vector<VolumeBeam>& beams = hit_points_.beams;
  const bool global = c_.settings.radius_schedule == RadiusSchedule::Global;
  if (c_.analysis.trace_photons && !c_.photon_pass.gather_beams(*c_.scene, beams, c_.cancel, poll, current_.counters))
    return false;
  sum_beam_band(first_pixel);
  if (global) return true;
  for (size_t p = 0; p < beam_band_.size(); ++p) {
    const VolumeFound& f = beam_band_[p];
    const uint32_t samples = pixel_samples ? pixel_samples[first_pixel + p] : 1;
    const double ratio = beam_pixels_[first_pixel + p].fold_in(1, (f.m + samples / 2) / samples, f.tau,
                                                               c_.settings.alpha, c_.settings.threshold);
    if (!beam_components_.empty()) beam_components_[first_pixel + p].fold(beam_parts_[p].tau, ratio);
  }
  return true;
}

// The band's beams summed per band pixel: crossing count and flux, and their radiance from this
// pass alone at the radius they gathered with (a 1-D kernel's: beam_radiance_scale).
void StochasticHitPoints::sum_beam_band(size_t first_pixel) {
  const double photons = pass_photons();
  clear_band(beam_band_, beam_parts_);
  for (const VolumeBeam& b : hit_points_.beams) {
    VolumeFound& f = beam_band_[b.pixel - first_pixel];
    const float scale = static_cast<float>(c_.beam_radiance_scale(b.r2, photons));
    f.m += b.m, f.tau += b.tau, f.radiance += b.tau * scale, f.bias += b.pass_bias * scale;
    if (beam_parts_.empty()) continue;
    VolumeParts& parts = beam_parts_[b.pixel - first_pixel];
    const int k = volume_slot(b.route);
    parts.tau[k] += b.tau, parts.radiance[k] += b.tau * scale;
  }
}

// `found` zeroed for each of the band's pixels, and `parts` too with component passes (else empty).
void StochasticHitPoints::clear_band(std::vector<VolumeFound>& found, std::vector<VolumeParts>& parts) const {
  const size_t band_pixels = hit_points_.pixel_begin.size() - 1;
  found.assign(band_pixels, VolumeFound{0, Vec3f(0.0f), Vec3f(0.0f), Vec3f(0.0f), 0.0f});
  parts.assign(components_.empty() ? 0 : band_pixels, VolumeParts{});
}

// The global schedule in a medium: every hit point gathers at its own initial radius times the
// factor of pass `index` for a sphere (radius_schedule.h: r^3 follows the surface's product, so r^2
// shrinks by its 2/3 power), as surface hit points do at theirs (start_at_global_radii); no initial
// radius below the volume photons' spacing.
void StochasticHitPoints::start_volume_at_global_radii(uint64_t index) {
  const double factor = global_radius_factor_in(3, index, c_.settings.alpha);
  for (VolumeHitPoint& h : hit_points_.volume)
    h.r2 = static_cast<float>(std::max<double>(h.r2, c_.min_volume_r2) * factor);
}

// The band's hit points in media summed per band pixel: photon count and flux, direct light, and
// the photons' radiance from this pass alone, each hit point's at the radius it gathered with.
void StochasticHitPoints::sum_volume_band(size_t first_pixel) {
  const double photons = pass_photons();
  clear_band(volume_band_, volume_parts_);
  for (const VolumeHitPoint& h : hit_points_.volume) {
    VolumeFound& f = volume_band_[h.pixel - first_pixel];
    const float scale = static_cast<float>(c_.volume_radiance_scale(h.r2, photons));
    const Vec3f radiance = h.tau * scale;
    const Vec3f tau = h.tau * density_form(h);
    if (c_.analysis.trace_photons) f.m += h.m, f.tau += tau, f.radiance += radiance, f.bias += h.pass_bias * scale;
    if (c_.analysis.sample_direct) f.direct += h.direct;
    if (volume_parts_.empty()) continue;
    VolumeParts& parts = volume_parts_[h.pixel - first_pixel];
    const int k = volume_slot(h.route);
    if (c_.analysis.trace_photons) parts.tau[k] += tau, parts.radiance[k] += radiance;
    if (c_.analysis.sample_direct) parts.direct[k] += h.direct;
  }
}

// The progressive radii: a hit point's flux as if gathered at its pixel's radius, which is the
// shrink s^2 (r^2 = its initial r^2 times s^2): flux times s^3 / r^3 (its own share of the 3-D
// estimate, whatever its initial radius). With the global schedule: its flux.
float StochasticHitPoints::density_form(const VolumeHitPoint& h) const {
  if (volume_pixels_.empty()) return 1.0f;
  if (!(h.r2 > 0.0f)) return 0.0f;  // a radius flushed to zero gathered nothing
  const double s2 = volume_pixels_[h.pixel].r2;
  const double ratio = s2 / static_cast<double>(h.r2);
  return static_cast<float>(ratio * std::sqrt(ratio));
}

void StochasticHitPoints::add_volume_direct(size_t p, ComponentLight& light) const {
  if (volume_parts_.empty()) return;
  for (int k = 0; k < kVolumeSlots; ++k) light.light[volume_direct_component(k)] += volume_parts_[p].direct[k];
}

void StochasticHitPoints::add_volume_radiance(size_t p, ComponentLight& light) const {
  if (volume_parts_.empty()) return;
  for (int k = 0; k < kVolumeSlots; ++k) light.light[volume_photon_component(k)] += volume_parts_[p].radiance[k];
  if (beam_parts_.empty()) return;
  for (int k = 0; k < kVolumeSlots; ++k) light.light[volume_photon_component(k)] += beam_parts_[p].radiance[k];
}

// Every hit point gathers with its pixel's current radius; a pixel's first comes from its first
// hit point (no smaller than the photons' spacing, photon_density_radius.h).
void StochasticHitPoints::start_at_pixel_radii(size_t first_pixel) {
  HitPoints& fresh = hit_points_;
  const size_t band_pixels = fresh.pixel_begin.size() - 1;
  for (size_t p = 0; p < band_pixels; ++p) {
    PixelStats& px = pixels_[first_pixel + p];
    for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
      if (px.r2 == 0.0f) {
        px.r2 = static_cast<float>(std::max(fresh.points[i].r2, c_.min_initial_r2));
        c_.stats.radii_widened += fresh.points[i].r2 < c_.min_initial_r2;
      }
      fresh.points[i].r2 = px.r2;
    }
  }
}

// The global schedule (radius_schedule.h): every hit point gathers at its own initial radius (as a
// pixel's first, above) times the factor of pass `index` (1 for the still's first).
void StochasticHitPoints::start_at_global_radii(size_t first_pixel, uint64_t index) {
  HitPoints& fresh = hit_points_;
  const double factor = global_radius_factor(index, c_.settings.alpha);
  const size_t band_pixels = fresh.pixel_begin.size() - 1;
  for (size_t p = 0; p < band_pixels; ++p) {
    PixelStats& px = pixels_[first_pixel + p];
    for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
      HitPoint& h = fresh.points[i];
      c_.stats.radii_widened += px.r2 == 0.0f && h.r2 < c_.min_initial_r2;
      h.r2 = std::max(h.r2, c_.min_initial_r2) * factor;
      px.r2 = static_cast<float>(h.r2);  // the pixel's latest, for radius_mean()
    }
  }
}

// Band pixel p's light components from this pass: in `light`, what needs no photons (its eye paths'
// emission after a bounce and Color passes, its hit points' direct light); in `photons`, its hit
// points' photon flux by slot (light_components.h), hit point i's times `photon_scale(i)`.
template <class Scale>
void StochasticHitPoints::pass_components(size_t p, ComponentLight& light, Vec3f photons[], Scale&& photon_scale) const {
  const HitPoints& fresh = hit_points_;
  light = fresh.pixel_components[p];
  for (int k = 0; k < kPhotonParts; ++k) photons[k] = Vec3f(0.0f);
  for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
    const HitPointComponents& h = fresh.components[i];
    const uint8_t route = fresh.route[i];
    const float scale = static_cast<float>(photon_scale(i));
    for (int c = 0; c < kLightClasses; ++c) {
      light.light[direct_component(route, c)] += h.direct[c];
      photons[photon_slot(route, c)] += h.tau_m[c] * scale;
    }
    photons[kLightClasses] += h.tau_m[kLightClasses] * scale;
  }
}

// The band's findings into its pixels (pass number `pass`, 1 for the first), with the same
// cross-generation rule as fixed hit points, per pixel. With several eye samples in a pixel
// (`pixel_samples`, adaptive_samples.h) the pass's value is their mean (each hit point carries 1 /
// samples), and so is the photon count the radius update sees: summed, it would shrink the radius
// of a pixel with 4 samples 4 times as fast as its neighbours'.
// The pixel's value from this pass alone and its bias estimate go to the error estimate
// (error_estimate.h), at the radius the photons were gathered with.
void StochasticHitPoints::fold_band(size_t first_pixel, uint64_t pass, const uint8_t* pixel_samples) {
  const HitPoints& fresh = hit_points_;
  const size_t band_pixels = fresh.pixel_begin.size() - 1;
  const double photons = pass_photons();
  parallel_for(c_.threads, band_pixels, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      uint32_t m = 0;
      Color tau_m(0.0), light = fresh.emitted[p];
      double pass_flux = 0.0, pass_bias = 0.0;
      for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
        m += fresh.stats[i].m;
        tau_m += fresh.stats[i].tau_m;
        light += fresh.stats[i].direct;
        pass_flux += fresh.stats[i].pass_flux;
        pass_bias += fresh.stats[i].pass_bias;
      }
      const uint32_t samples = pixel_samples ? pixel_samples[first_pixel + p] : 1;
      m = (m + samples / 2) / samples;  // the photons of the pixel's mean sample, rounded
      PixelStats& px = pixels_[first_pixel + p];
      const double scale = c_.pass_radiance_scale(px.r2, photons);
      errors_[first_pixel + p].add(luminance(light) + scale * pass_flux + volume_pass_value(p),
                                   scale * pass_bias + volume_pass_bias(p), pass);
      const PixelPass found{m, Vec3f(tau_m), Vec3f(light), static_cast<float>(fresh.transparency[p])};
      const double ratio = fold_pass(px, found, pass, c_.settings.alpha, c_.settings.threshold);
      fold_seen(first_pixel + p, p, pass);
      if (!components_.empty()) {
        ComponentLight light_parts;
        Vec3f photon_parts[kPhotonParts];
        pass_components(p, light_parts, photon_parts, [](uint32_t) { return 1.0; });
        add_volume_direct(p, light_parts);
        components_[first_pixel + p].fold(light_parts, photon_parts, pass, ratio);
      }
    }
  });
}

// The same with the global schedule: each hit point's photons are radiance at its own radius, and
// the pixel keeps only the mean of its pass values (in `light`; tau stays 0), as Knaus & Zwicker's
// image is the mean of the passes' estimates.
void StochasticHitPoints::fold_band_global(size_t first_pixel, uint64_t pass) {
  const HitPoints& fresh = hit_points_;
  const size_t band_pixels = fresh.pixel_begin.size() - 1;
  const double photons = pass_photons();
  parallel_for(c_.threads, band_pixels, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      Color light = fresh.emitted[p], photon_light(0.0);
      double pass_value = 0.0, pass_bias = 0.0;
      for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
        const HitPointStats& s = fresh.stats[i];
        const double scale = c_.pass_radiance_scale(fresh.points[i].r2, photons);
        light += s.direct;
        photon_light += c_.photon_radiance(fresh.points[i].r2, s, photons);
        pass_value += scale * s.pass_flux;
        pass_bias += scale * s.pass_bias;
      }
      if (media_) photon_light += Color(volume_band_[p].radiance);  // its hit points' in media
      if (beams_) photon_light += Color(beam_band_[p].radiance);     // and beams
      errors_[first_pixel + p].add(luminance(light) + pass_value + volume_pass_value(p),
                                   pass_bias + volume_pass_bias(p), pass);
      const PixelPass found{0, Vec3f(0.0f), Vec3f(light + photon_light), static_cast<float>(fresh.transparency[p])};
      fold_pass(pixels_[first_pixel + p], found, pass, c_.settings.alpha, c_.settings.threshold);
      fold_seen(first_pixel + p, p, pass);
      if (!components_.empty()) {  // the photons' radiance joins the means, as the pixel's does
        ComponentLight light_parts;
        Vec3f photon_parts[kPhotonParts];
        pass_components(p, light_parts, photon_parts,
                        [&](uint32_t i) { return c_.pass_radiance_scale(fresh.points[i].r2, photons); });
        for (int k = 0; k < kPhotonParts; ++k) light_parts.light[photon_slot_component(k)] += photon_parts[k];
        for (Vec3f& f : photon_parts) f = Vec3f(0.0f);
        add_volume_direct(p, light_parts);
        add_volume_radiance(p, light_parts);
        components_[first_pixel + p].fold(light_parts, photon_parts, pass, 0.0);
      }
    }
  });
}

// With light passes: band pixel `p`'s seen light into image pixel `pixel`'s running means.
void StochasticHitPoints::fold_seen(size_t pixel, size_t p, uint64_t pass) {
  if (seen_.empty()) return;
  SeenMeans& mean = seen_[pixel];
  const float w = 1.0f / static_cast<float>(pass);
  mean.emission += (Vec3f(hit_points_.seen[p].emission) - mean.emission) * w;
  mean.environment += (Vec3f(hit_points_.seen[p].environment) - mean.environment) * w;
}

PixelValue StochasticHitPoints::pixel(size_t p) const {
  const PixelStats& px = pixels_[p];
  // The rows a cancelled pass completed have its photons too.
  const bool in_pass = p < static_cast<size_t>(current_.next_row) * c_.scene->camera().width;
  const double emitted = static_cast<double>(in_pass ? current_.counters.emitted : c_.stats.photon.emitted);
  Color volume(0.0);
  if (!volume_pixels_.empty()) {
    const FloatPhotonStats& v = volume_pixels_[p];
    if (c_.analysis.trace_photons)
      volume = volume_photon_radiance(v.r2, v.in_double(), emitted, c_.lights.flux_unit());
  }
  if (!beam_pixels_.empty()) {
    const FloatPhotonStats& b = beam_pixels_[p];
    volume += (Color(b.tau) + Color(b.tau_m)) * c_.beam_radiance_scale(b.r2, emitted);
  }
  return PixelValue{Color(px.light) + c_.photon_radiance(px.r2, px.in_double(), emitted) + volume, px.transparency};
}

ComponentLight StochasticHitPoints::components(size_t p) const {
  if (components_.empty()) return ComponentLight{};
  const bool in_pass = p < static_cast<size_t>(current_.next_row) * c_.scene->camera().width;
  const double emitted = static_cast<double>(in_pass ? current_.counters.emitted : c_.stats.photon.emitted);
  ComponentLight out = components_[p].value(c_.pass_radiance_scale(pixels_[p].r2, emitted));
  if (!volume_components_.empty())
    volume_components_[p].add_to(out, c_.volume_radiance_scale(volume_pixels_[p].r2, emitted));
  if (!beam_components_.empty())
    beam_components_[p].add_to(out, c_.beam_radiance_scale(beam_pixels_[p].r2, emitted));
  return out;
}

SeenLight StochasticHitPoints::seen(size_t p) const {
  if (seen_.empty()) return SeenLight{};
  return SeenLight{Color(seen_[p].emission), Color(seen_[p].environment)};
}

double StochasticHitPoints::pass_done() const {
  return static_cast<double>(current_.next_row) / c_.scene->camera().height;
}

double StochasticHitPoints::radius_mean() const {
  double sum = 0.0;
  size_t count = 0;
  for (const PixelStats& px : pixels_)
    if (px.r2 > 0.0f) sum += std::sqrt(static_cast<double>(px.r2)), ++count;
  return count ? sum / count : 0.0;
}

void StochasticHitPoints::add_memory(MemoryUse& use) const {
  use.pixels += pixels_.capacity() * sizeof(PixelStats) + errors_.capacity() * sizeof(PixelErrorStats) +
                depth_.capacity() * sizeof(float) + eye_samples_.capacity() + seen_.capacity() * sizeof(SeenMeans) +
                components_.capacity() * sizeof(PixelComponents) +
                (volume_pixels_.capacity() + beam_pixels_.capacity()) * sizeof(FloatPhotonStats) +
                (volume_components_.capacity() + beam_components_.capacity()) * sizeof(PixelVolumeComponents);
  use.hit_points += (volume_band_.capacity() + beam_band_.capacity()) * sizeof(VolumeFound) +
                    (volume_parts_.capacity() + beam_parts_.capacity()) * sizeof(VolumeParts);
  use.hit_points += hit_points_.memory_bytes() + eye_scratch_.memory_bytes();
}

}  // namespace ppm
