// The render loop (see renderer.h).
#include "ppm/renderer.h"

#include "ppm/direct_light.h"
#include "ppm/eye_pass.h"
#include "ppm/parallel.h"
#include "ppm/photon_density_radius.h"
#include "ppm/progressive.h"
#include "post/dof_post.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
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

// A finite radiance above float range saturates instead of becoming inf (the
// conversion is undefined behaviour in C++); NaN and inf stay visible.
float to_float(double v) { return std::isfinite(v) && std::fabs(v) > FLT_MAX ? std::copysign(FLT_MAX, v) : static_cast<float>(v); }

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

Renderer::Renderer(std::shared_ptr<const Scene> scene, const Settings& settings)
    : scene_(std::move(scene)),
      settings_((settings.validate(), settings)),
      threads_(resolve_threads(settings.threads)),
      lights_(checked(scene_).lights(), settings_.scene_analysis),
      analysis_(analyse_scene(*scene_, lights_, settings_)),
      photon_pass_(settings_, threads_) {
  stats_.threads = threads_;
  stats_.skipped = analysis_.skipped;
  decide_depth_of_field();
  scene_->attach_renderer();
}

Renderer::~Renderer() { scene_->detach_renderer(); }

// Depth of field costs a depth buffer and a blur (POST) or lens sampling
// (LENS); skip both when it is off or cannot blur anything by a pixel.
void Renderer::decide_depth_of_field() {
  const Camera& cam = scene_->camera();
  if (settings_.dof_mode == DofMode::Off) {
    stats_.skipped.push_back("depth of field: off (no depth buffer, blur or lens sampling)");
    return;
  }
  const Aabb b = scene_->bounds();
  double near = kInf, far = 0.0;
  for (int i = 0; i < 8 && !b.empty(); ++i) {
    const Vec3 corner((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
    const double z = cam.depth_of(corner);
    near = std::fmin(near, z);
    far = std::fmax(far, z);
  }
  if (settings_.scene_analysis && (b.empty() || far <= 0.0 || max_coc_pixels(cam, near, far) < 1.0)) {
    stats_.skipped.push_back("depth of field: circle of confusion under a pixel over the scene's depth range");
    return;
  }
  dof_post_ = settings_.dof_mode == DofMode::Post;
  dof_lens_ = settings_.dof_mode == DofMode::Lens;
}

EyePassOptions Renderer::eye_options(uint64_t generation) const {
  EyePassOptions o;
  o.threads = threads_;
  o.follow_specular = analysis_.follow_specular;
  o.use_textures = analysis_.use_textures;
  o.samples_per_pixel = settings_.hit_points == HitPointMode::Stochastic ? 1 : settings_.samples_per_pixel;
  o.generation = generation;
  o.lens = dof_lens_;
  o.record_depth = dof_post_ && depth_.empty();
  return o;
}

bool Renderer::ensure_eye_pass(const std::function<bool()>& poll) {
  if (eye_done_) return true;
  if (settings_.hit_points == HitPointMode::Stochastic) {
    const Camera& cam = scene_->camera();
    pixels_.assign(static_cast<size_t>(cam.width) * cam.height, PixelStats{});
    eye_done_ = true;
    return true;
  }
  const auto t0 = Clock::now();
  if (!eye_pass(*scene_, settings_, eye_options(0), hit_points_, cancel_, poll)) return false;
  if (!hit_points_.depth.empty()) depth_.swap(hit_points_.depth);
  if (!measure_photon_spacing_once(hit_points_, poll)) return false;
  eye_done_ = true;
  stats_.eye_seconds = since(t0);
  stats_.hit_points = hit_points_.size();
  double sum = 0.0;
  for (HitPoint& h : hit_points_.points) {
    if (h.r2 < min_initial_r2_) h.r2 = min_initial_r2_, ++stats_.radii_widened;
    sum += std::sqrt(h.r2);
  }
  stats_.initial_radius_mean = hit_points_.size() ? sum / hit_points_.size() : 0.0;
  const size_t pixels = static_cast<size_t>(scene_->camera().width) * scene_->camera().height;
  size_t empty = 0;
  for (size_t p = 0; p < pixels; ++p) empty += hit_points_.pixel_begin[p] == hit_points_.pixel_begin[p + 1];
  if (empty > 0)
    stats_.skipped.push_back("hit points: " + std::to_string(empty) +
                             " pixels see only background, emitters or nothing");
  return true;
}

// The photons' spacing, once per render, before any initial radius is set (automatic radii only).
bool Renderer::measure_photon_spacing_once(const HitPoints& hp, const std::function<bool()>& poll) {
  if (spacing_measured_ || !settings_.density_radius || settings_.initial_radius > 0.0 || !analysis_.trace_photons ||
      hp.size() == 0)
    return true;
  double start = 0.0;  // where the neighbour search begins: the hit points' mean radius
  for (const HitPoint& h : hp.points) start += std::sqrt(h.r2);
  PhotonSpacing spacing;
  if (!measure_photon_spacing(*scene_, lights_, settings_, threads_, start / hp.size(), cancel_, poll, spacing))
    return false;
  spacing_measured_ = true;
  min_initial_r2_ = spacing.radius * spacing.radius;
  stats_.photon_spacing = spacing.radius;
  stats_.density_radius_seconds = spacing.seconds;
  return true;
}

bool Renderer::one_pass(const std::function<bool()>& poll) {
  const uint64_t pass = stats_.passes;
  // Photons first: a pass cancelled inside the photon pass leaves no trace.
  if (analysis_.trace_photons) {
    PhotonPassCounters counters = stats_.photon;
    if (!photon_pass_.run(*scene_, lights_, pass, hit_points_, cancel_, poll, counters)) return false;
    stats_.photon = counters;
  } else {
    stats_.photon.emitted += settings_.photons_per_pass;  // an empty pass still counts its photons
  }
  // Direct light adds its sums only when complete, so a cancel here keeps the image consistent.
  bool completed = true;
  if (analysis_.sample_direct && (analysis_.resample_direct || stats_.direct_samples == 0)) {
    const auto t0 = Clock::now();
    completed = direct_light_pass(*scene_, lights_, settings_, pass, threads_, hit_points_, direct_sums_, cancel_, poll);
    if (completed) ++stats_.direct_samples;
    stats_.direct_seconds += since(t0);
  }
  const auto t0 = Clock::now();
  parallel_for(threads_, hit_points_.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i)
      progressive_update(hit_points_.points[i].r2, hit_points_.stats[i], settings_.alpha, settings_.threshold);
  });
  stats_.update_seconds += since(t0);
  ++stats_.passes;
  return completed;
}

bool Renderer::stochastic_pass(const std::function<bool()>& poll) {
  const uint64_t pass = stats_.passes;
  auto t0 = Clock::now();
  HitPoints& fresh = spare_hit_points_;  // reused: no pass allocates hit points once sizes settle
  if (!eye_pass(*scene_, settings_, eye_options(pass + 1), fresh, cancel_, poll)) return false;
  stats_.eye_seconds += since(t0);
  if (!measure_photon_spacing_once(fresh, poll)) return false;
  // Every hit point gathers with its pixel's current radius; a pixel's first comes from its first hit point.
  const size_t pixel_count = pixels_.size();
  for (size_t p = 0; p < pixel_count; ++p)
    for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
      if (pixels_[p].r2 == 0.0) {
        pixels_[p].r2 = std::max(fresh.points[i].r2, min_initial_r2_);
        stats_.radii_widened += fresh.points[i].r2 < min_initial_r2_;
      }
      fresh.points[i].r2 = pixels_[p].r2;
    }
  // Photons and direct light into the fresh hit points; a cancel drops the whole pass.
  PhotonPassCounters counters = stats_.photon;
  photon_pass_.reset_index();
  if (analysis_.trace_photons && !photon_pass_.run(*scene_, lights_, pass, fresh, cancel_, poll, counters))
    return false;
  if (!analysis_.trace_photons) counters.emitted += settings_.photons_per_pass;
  if (analysis_.sample_direct) {
    t0 = Clock::now();
    if (!direct_light_pass(*scene_, lights_, settings_, pass, threads_, fresh, direct_sums_, cancel_, poll)) return false;
    stats_.direct_seconds += since(t0);
  }
  // Fold the pass into the pixels: the same cross-generation rule, per pixel.
  t0 = Clock::now();
  parallel_for(threads_, pixel_count, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      PixelStats& px = pixels_[p];
      for (uint32_t i = fresh.pixel_begin[p]; i < fresh.pixel_begin[p + 1]; ++i) {
        px.stats.m += fresh.stats[i].m;
        px.stats.tau_m += fresh.stats[i].tau_m;
        px.stats.direct += fresh.stats[i].direct;
      }
      px.emitted += fresh.emitted[p];
      px.transparency += fresh.transparency[p];
      progressive_update(px.r2, px.stats, settings_.alpha, settings_.threshold);
    }
  });
  if (!fresh.depth.empty()) depth_.swap(fresh.depth);
  stats_.update_seconds += since(t0);
  stats_.photon = counters;
  if (analysis_.sample_direct) ++stats_.direct_samples;
  stats_.hit_points = fresh.size();
  std::swap(hit_points_, spare_hit_points_);
  ++stats_.passes;
  return true;
}

uint64_t Renderer::run(uint64_t passes, double seconds, const std::function<bool(const Progress&)>& poll) {
  if (passes == 0 && !(seconds > 0.0)) throw std::invalid_argument("run: give passes > 0 or seconds > 0");
  if (!(seconds >= 0.0)) throw std::invalid_argument("run: seconds must be >= 0");
  if (running_.exchange(true)) throw std::runtime_error("run: this renderer is already running");
  struct Done {
    std::atomic<bool>& flag;
    ~Done() { flag = false; }
  } done{running_};
  cancel_ = false;
  stats_.cancelled = false;
  const auto t0 = Clock::now();
  const uint64_t start = stats_.passes;
  auto last_callback = Clock::now();
  auto inner_poll = [&]() {
    // A time limit ends the pass in progress too, once at least one pass is done.
    if (seconds > 0.0 && since(t0) >= seconds && stats_.passes > start) return false;
    if (!poll || since(last_callback) < settings_.progress_interval) return true;
    last_callback = Clock::now();
    return poll(Progress{stats_.passes, stats_.photon.emitted, since(t0)});
  };
  bool ok = ensure_eye_pass(inner_poll);
  while (ok && (passes == 0 || stats_.passes - start < passes)) {
    if (seconds > 0.0 && since(t0) >= seconds) break;
    ok = settings_.hit_points == HitPointMode::Stochastic ? stochastic_pass(inner_poll) : one_pass(inner_poll);
    if (ok && poll && !poll(Progress{stats_.passes, stats_.photon.emitted, since(t0)})) ok = false;
    last_callback = Clock::now();
  }
  const bool timed_out = seconds > 0.0 && since(t0) >= seconds;
  stats_.cancelled = !ok && !timed_out;
  stats_.total_seconds += since(t0);
  return stats_.passes - start;
}

namespace {
size_t memory_bytes(const HitPoints& h) {
  return h.points.capacity() * sizeof(HitPoint) + h.shading.capacity() * sizeof(HitPointShading) +
         h.stats.capacity() * sizeof(HitPointStats) + h.pixel_begin.capacity() * sizeof(uint32_t) +
         h.emitted.capacity() * sizeof(Color) + h.transparency.capacity() * sizeof(double) +
         h.depth.capacity() * sizeof(float) + h.chain.capacity() * sizeof(Bounces);
}

void refuse_while_running(const std::atomic<bool>& running, const char* what) {
  if (running)
    throw std::runtime_error(std::string(what) +
                             ": not available while run() is in progress; use the callback's info, or call it "
                             "between runs (e.g. run(passes=1) in a loop)");
}
}  // namespace

std::vector<float> Renderer::image() const {
  refuse_while_running(running_, "image()");
  const Camera& cam = scene_->camera();
  const int W = cam.width, H = cam.height;
  std::vector<float> rgba(static_cast<size_t>(W) * H * 4, 0.0f);
  if (!eye_done_) {  // black, but alpha = 1 as documented
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 1.0f;
    return rgba;
  }
  const double emitted = static_cast<double>(stats_.photon.emitted);
  const bool stochastic = settings_.hit_points == HitPointMode::Stochastic;
  const double direct_scale = stats_.direct_samples > 0 ? 1.0 / stats_.direct_samples : 0.0;
  const double pass_scale = stats_.passes > 0 ? 1.0 / stats_.passes : 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t p = static_cast<size_t>(y) * W + x;
      Color c(0.0);
      double transparency;
      if (stochastic) {
        const PixelStats& px = pixels_[p];
        transparency = px.transparency * pass_scale;
        c = px.emitted * pass_scale + px.stats.direct * direct_scale;
        if (analysis_.trace_photons && px.r2 > 0.0) c += photon_radiance(px.r2, px.stats, emitted, lights_.flux_unit());
      } else {
        transparency = hit_points_.transparency[p];
        c = hit_points_.emitted[p];
        for (uint32_t i = hit_points_.pixel_begin[p]; i < hit_points_.pixel_begin[p + 1]; ++i) {
          const HitPointStats& s = hit_points_.stats[i];
          c += s.direct * direct_scale;
          if (analysis_.trace_photons) c += photon_radiance(hit_points_.points[i].r2, s, emitted, lights_.flux_unit());
        }
      }
      float* out = &rgba[(static_cast<size_t>(H - 1 - y) * W + x) * 4];  // top row first
      out[0] = to_float(c.x);
      out[1] = to_float(c.y);
      out[2] = to_float(c.z);
      out[3] = static_cast<float>(std::clamp(1.0 - transparency, 0.0, 1.0));  // RGB is premultiplied by it
    }
  if (dof_post_ && depth_.size() == static_cast<size_t>(W) * H) {
    std::vector<float> depth(depth_.size());
    for (int y = 0; y < H; ++y)  // to top row first, like the image
      std::copy_n(&depth_[static_cast<size_t>(H - 1 - y) * W], W, &depth[static_cast<size_t>(y) * W]);
    rgba = settings_.dof_post_preset == DofPostPreset::ReportThirds ? dof_post_report_thirds(rgba, depth, W, H)
                                                                    : dof_post_thin_lens(rgba, depth, cam, settings_.dof_max_radius);
  }
  return rgba;
}

RenderStats Renderer::stats() const {
  refuse_while_running(running_, "stats()");
  RenderStats s = stats_;
  s.photons_emitted = stats_.photon.emitted;
  s.photons_deposited = stats_.photon.deposited;
  double sum = 0.0;
  size_t count = 0;
  if (settings_.hit_points == HitPointMode::Stochastic) {
    for (const PixelStats& px : pixels_)
      if (px.r2 > 0.0) sum += std::sqrt(px.r2), ++count;
  } else {
    for (const HitPoint& h : hit_points_.points) sum += std::sqrt(h.r2), ++count;
  }
  s.radius_mean = count ? sum / count : 0.0;
  s.memory_bytes = pixels_.capacity() * sizeof(PixelStats) + depth_.capacity() * sizeof(float) +
                   photon_pass_.memory_bytes() + memory_bytes(hit_points_) + memory_bytes(spare_hit_points_) +
                   direct_sums_.capacity() * sizeof(Color);
  return s;
}

}  // namespace ppm
