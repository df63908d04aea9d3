// The render loop (see renderer.h).
#include "ppm/renderer.h"

#include "ppm/direct_light.h"
#include "ppm/eye_pass.h"
#include "ppm/progressive.h"

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

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

Renderer::Renderer(std::shared_ptr<const Scene> scene, const Settings& settings)
    : scene_(std::move(scene)),
      settings_((settings.validate(), settings)),
      threads_(resolve_threads(settings.threads)),
      lights_(checked(scene_).lights()),
      analysis_(analyse_scene(*scene_, lights_, settings_)),
      photon_pass_(settings_, threads_) {
  stats_.threads = threads_;
  stats_.skipped = analysis_.skipped;
  scene_->attach_renderer();
}

Renderer::~Renderer() { scene_->detach_renderer(); }

bool Renderer::ensure_eye_pass(const std::function<bool()>& poll) {
  if (eye_done_) return true;
  const auto t0 = Clock::now();
  EyePassOptions options{threads_, analysis_.follow_specular, analysis_.use_textures};
  if (!eye_pass(*scene_, settings_, options, hit_points_, cancel_, poll)) return false;
  eye_done_ = true;
  stats_.eye_seconds = since(t0);
  stats_.hit_points = hit_points_.size();
  const size_t pixels = static_cast<size_t>(scene_->camera().width) * scene_->camera().height;
  size_t empty = 0;
  for (size_t p = 0; p < pixels; ++p) empty += hit_points_.pixel_begin[p] == hit_points_.pixel_begin[p + 1];
  if (empty > 0)
    stats_.skipped.push_back("hit points: " + std::to_string(empty) +
                             " pixels see only background, emitters or nothing");
  double sum = 0.0;
  for (const HitPoint& h : hit_points_.points) sum += std::sqrt(h.r2);
  stats_.initial_radius_mean = hit_points_.size() ? sum / hit_points_.size() : 0.0;
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
    completed = direct_light_pass(*scene_, lights_, settings_, pass, threads_, hit_points_, cancel_, poll);
    if (completed) ++stats_.direct_samples;
    stats_.direct_seconds += since(t0);
  }
  const auto t0 = Clock::now();
  for (size_t i = 0; i < hit_points_.size(); ++i)
    progressive_update(hit_points_.points[i], hit_points_.stats[i], settings_.alpha, settings_.threshold);
  stats_.update_seconds += since(t0);
  ++stats_.passes;
  return completed;
}

uint64_t Renderer::run(uint64_t passes, double seconds, const std::function<bool(const Progress&)>& poll) {
  if (passes == 0 && !(seconds > 0.0)) throw std::invalid_argument("run: give passes > 0 or seconds > 0");
  if (!(seconds >= 0.0)) throw std::invalid_argument("run: seconds must be >= 0");
  cancel_ = false;
  stats_.cancelled = false;
  const auto t0 = Clock::now();
  const uint64_t start = stats_.passes;
  auto inner_poll = [&]() {
    // A time limit ends the pass in progress too, once at least one pass is done.
    if (seconds > 0.0 && since(t0) >= seconds && stats_.passes > start) return false;
    return poll ? poll(Progress{stats_.passes, stats_.photon.emitted, since(t0)}) : true;
  };
  bool ok = ensure_eye_pass(inner_poll);
  while (ok && (passes == 0 || stats_.passes - start < passes)) {
    if (seconds > 0.0 && since(t0) >= seconds) break;
    ok = one_pass(inner_poll);
    if (ok && poll && !poll(Progress{stats_.passes, stats_.photon.emitted, since(t0)})) ok = false;
  }
  const bool timed_out = seconds > 0.0 && since(t0) >= seconds;
  stats_.cancelled = !ok && !timed_out;
  stats_.total_seconds += since(t0);
  return stats_.passes - start;
}

std::vector<float> Renderer::image() const {
  const Camera& cam = scene_->camera();
  const int W = cam.width, H = cam.height;
  std::vector<float> rgba(static_cast<size_t>(W) * H * 4, 0.0f);
  if (!eye_done_) return rgba;
  const double emitted = static_cast<double>(stats_.photon.emitted);
  const double direct_scale = stats_.direct_samples > 0 ? 1.0 / stats_.direct_samples : 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t p = static_cast<size_t>(y) * W + x;
      Color c = hit_points_.emitted[p];
      for (uint32_t i = hit_points_.pixel_begin[p]; i < hit_points_.pixel_begin[p + 1]; ++i) {
        const HitPointStats& s = hit_points_.stats[i];
        c += s.direct * direct_scale;
        if (analysis_.trace_photons) c += photon_radiance(hit_points_.points[i], s, emitted);
      }
      float* out = &rgba[(static_cast<size_t>(H - 1 - y) * W + x) * 4];  // top row first
      out[0] = static_cast<float>(c.x);
      out[1] = static_cast<float>(c.y);
      out[2] = static_cast<float>(c.z);
      out[3] = 1.0f;
    }
  return rgba;
}

RenderStats Renderer::stats() const {
  RenderStats s = stats_;
  s.photons_emitted = stats_.photon.emitted;
  s.photons_deposited = stats_.photon.deposited;
  double sum = 0.0;
  for (const HitPoint& h : hit_points_.points) sum += std::sqrt(h.r2);
  s.radius_mean = hit_points_.size() ? sum / hit_points_.size() : 0.0;
  s.memory_bytes = photon_pass_.memory_bytes() + hit_points_.points.capacity() * sizeof(HitPoint) +
                   hit_points_.shading.capacity() * sizeof(HitPointShading) +
                   hit_points_.stats.capacity() * sizeof(HitPointStats) +
                   hit_points_.pixel_begin.capacity() * sizeof(uint32_t) + hit_points_.emitted.capacity() * sizeof(Color);
  return s;
}

}  // namespace ppm
