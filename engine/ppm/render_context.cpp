// The shared part of a render (see render_context.h).
#include "ppm/render_context.h"

#include "post/dof_post.h"
#include "base/parallel.h"
#include "ppm/photon_density_radius.h"
#include "ppm/progressive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace ppm {
namespace {

int resolve_threads(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 1;
}

const Scene& checked(const std::shared_ptr<const Scene>& scene) {
  if (!scene) throw std::invalid_argument("Renderer: scene is null");
  if (!scene->built()) throw std::invalid_argument("Renderer: scene is not built");
  if (!scene->has_camera()) throw std::invalid_argument("Renderer: the scene has no camera (call set_camera)");
  return *scene;
}

}  // namespace

RenderContext::RenderContext(std::shared_ptr<const Scene> scene_in, const Settings& settings_in)
    : scene(std::move(scene_in)),
      settings((settings_in.validate(), settings_in)),
      lease(checked(scene)),
      threads(resolve_threads(settings.threads)),
      lights(scene->lights(), settings.scene_analysis),
      analysis(analyse_scene(*scene, lights, settings)),
      photon_pass(settings, threads) {
  stats.threads = threads;
  stats.skipped = analysis.skipped;
  decide_depth_of_field();
}

// Depth of field costs a depth buffer and a blur (POST) or lens sampling
// (LENS); skip both when it is off or cannot blur anything by a pixel.
void RenderContext::decide_depth_of_field() {
  const Camera& cam = scene->camera();
  if (settings.dof_mode == DofMode::Off) {
    stats.skipped.push_back("depth of field: off (no depth buffer, blur or lens sampling)");
    return;
  }
  const Aabb b = scene->bounds();
  double near = kInf, far = 0.0;
  for (int i = 0; i < 8 && !b.empty(); ++i) {
    const Vec3 corner((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
    const double z = cam.depth_of(corner);
    near = std::fmin(near, z);
    far = std::fmax(far, z);
  }
  if (settings.scene_analysis && (b.empty() || far <= 0.0 || max_coc_pixels(cam, near, far) < 1.0)) {
    stats.skipped.push_back("depth of field: circle of confusion under a pixel over the scene's depth range");
    return;
  }
  dof_post = settings.dof_mode == DofMode::Post;
  dof_lens = settings.dof_mode == DofMode::Lens;
}

EyePassOptions RenderContext::eye_options(uint64_t generation, int samples_per_pixel) const {
  EyePassOptions o;
  o.threads = threads;
  o.follow_specular = analysis.follow_specular;
  o.samples_per_pixel = samples_per_pixel;
  o.generation = generation;
  o.lens = dof_lens;
  o.record_depth = dof_post && depth.empty();
  o.lights = &lights;
  return o;
}

bool RenderContext::measure_photon_spacing_once(const HitPoints& hp, const Poll& poll) {
  double sum = 0.0;
  for (const HitPoint& h : hp.points) sum += std::sqrt(h.r2);
  for (const VolumeHitPoint& h : hp.volume) sum += std::sqrt(h.r2);
  const size_t count = hp.size() + hp.volume.size();
  return measure_photon_spacing_once(count ? sum / count : 0.0, poll);
}

bool RenderContext::measure_photon_spacing_once(double mean_radius, const Poll& poll) {
  if (spacing_measured || !settings.density_radius || settings.initial_radius > 0.0 || !analysis.trace_photons)
    return true;
  // The neighbour search begins at the hit points' mean radius, or (a band of sky alone) a
  // thousandth of the scene's size: the distances found do not depend on it, the search's time does.
  double start = mean_radius;
  if (!(start > 0.0)) {
    const Aabb box = scene->bounds();
    start = 1e-3 * glm::length(box.hi - box.lo);
  }
  if (!(start > 0.0) || !std::isfinite(start)) return true;
  PhotonSpacing spacing;
  if (!measure_photon_spacing(*scene, lights, settings, threads, start, cancel, poll, spacing)) return false;
  spacing_measured = true;
  min_initial_r2 = spacing.radius * spacing.radius;
  const double volume_floor = settings.volume_radius_scale * spacing.volume_radius;  // scaled as the footprints
  min_volume_r2 = volume_floor * volume_floor;
  stats.photon_spacing = spacing.radius;
  stats.volume_photon_spacing = spacing.volume_radius;
  stats.density_radius_seconds = spacing.seconds;
  return true;
}

void RenderContext::weigh_pixels_for_guide(const std::vector<PixelErrorStats>& errors, const ErrorPasses& passes) {
  if (!settings.photon_guiding) return;
  if (passes.passes < kMinErrorPasses) {  // no noise estimate yet: the guide stays uniform
    photon_pass.set_guide_weights(nullptr);
    return;
  }
  guide_weights.resize(errors.size());
  double sum = 0.0;
  for (size_t p = 0; p < errors.size(); ++p) sum += std::fabs(pixel_error(errors[p], passes.of(p), 1.0).value);
  // A pixel's error counts alike wherever it is (the mean absolute error target_error halts on):
  // a photon bringing a share of a pixel's light is worth that share of its noise. Dark pixels'
  // shares are taken against a floor, so that no black pixel makes its few photons precious.
  const double floor = 0.05 * sum / std::max<size_t>(errors.size(), 1);
  parallel_for(threads, errors.size(), [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      const PixelError e = pixel_error(errors[p], passes.of(p), 1.0);
      const double w = e.sd / std::max(std::fabs(e.value), floor);
      guide_weights[p] = std::isfinite(w) && floor > 0.0 ? static_cast<float>(w) : 0.0f;
    }
  });
  photon_pass.set_guide_weights(&guide_weights);
}

bool RenderContext::run_photon_pass(HitPoints& hp, uint64_t pass, const Poll& poll, PhotonPassCounters& counters) {
  if (!analysis.trace_photons) {
    counters.emitted += settings.photons_per_pass;  // an empty pass still counts its photons
    return true;
  }
  return photon_pass.run(*scene, lights, pass, hp, cancel, poll, counters);
}

int RenderContext::band_rows(int samples_per_pixel) const {
  const Camera& cam = scene->camera();
  if (!photon_pass.indexes_photons()) return cam.height;
  return static_cast<int>(std::clamp<size_t>(kBandPixels / (size_t(cam.width) * samples_per_pixel), 1, cam.height));
}

bool RenderContext::run_bands(int& next_row, int rows, EyePassOptions& eye,
                              const std::function<bool(const EyePassOptions&)>& band) {
  const int height = scene->camera().height;
  for (int row = next_row; row < height; row += rows) {
    eye.row_begin = row;
    eye.row_end = std::min(height, row + rows);
    if (!band(eye)) return false;
    next_row = eye.row_end;
    if (next_row < height && pause_due && pause_due()) {
      paused = true;
      return false;
    }
  }
  return true;
}

bool RenderContext::gather_band(HitPoints& band, bool first_band, uint64_t pass, double typical_r2,
                                const Poll& poll, PhotonPassCounters& counters) {
  if (!analysis.trace_photons) {  // nothing to trace: the pass's photons are only counted, once
    if (first_band) counters.emitted += settings.photons_per_pass;
    return true;
  }
  if (!photon_pass.indexes_photons()) {  // one band: the whole pass at once
    photon_pass.reset_index();
    return photon_pass.run(*scene, lights, pass, band, cancel, poll, counters);
  }
  if (first_band && !photon_pass.trace_and_index(*scene, lights, pass, typical_r2, cancel, poll, counters))
    return false;
  return photon_pass.gather(*scene, band, cancel, poll, counters);
}

Color RenderContext::photon_radiance(double r2, const HitPointStats& s, double photons_emitted) const {
  if (!analysis.trace_photons) return Color(0.0);
  return ppm::photon_radiance(r2, s, photons_emitted, lights.flux_unit());
}

void RenderContext::add_memory(MemoryUse& use) const {
  use.scene += scene->memory_bytes();
  use.pixels += depth.capacity() * sizeof(float) + guide_weights.capacity() * sizeof(float);
  use.hit_points += photon_pass.per_hit_point_bytes() + direct_scratch.memory_bytes();
  use.photons += photon_pass.photon_bytes();
  use.index += photon_pass.index_bytes();
}

}  // namespace ppm
