// The render loop (see renderer.h); what differs between fixed and stochastic
// hit points is in the estimators (estimator.h).
#include "ppm/renderer.h"

#include "post/dof_post.h"
#include "ppm/denoising_features.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace ppm {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Fills `out`, W x H pixels of `channels` floats with the top row first, by fill(p, o): p the
// pixel's index with row 0 at the bottom (the estimators'), o its channels.
template <class Fill>
void fill_top_row_first(std::vector<float>& out, int W, int H, int channels, Fill&& fill) {
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      fill(static_cast<size_t>(y) * W + x, &out[(static_cast<size_t>(H - 1 - y) * W + x) * channels]);
}

void refuse_while_running(const std::atomic<bool>& running, const char* what) {
  if (running)
    throw std::runtime_error(std::string(what) +
                             ": not available while run() is in progress; use the callback's info, or call it "
                             "between runs (e.g. run(passes=1) in a loop)");
}

}  // namespace

Renderer::Renderer(std::shared_ptr<const Scene> scene, const Settings& settings)
    : context_(std::move(scene), settings), estimator_(make_estimator(context_)) {}

Renderer::~Renderer() = default;

std::unique_ptr<Renderer> make_renderer(const std::shared_ptr<Scene>& scene, const Settings& settings) {
  scene->build();
  scene->check_energy_range(settings.path_bounces());
  return std::make_unique<Renderer>(scene, settings);
}

uint64_t Renderer::run(uint64_t passes, double seconds, const std::function<bool(const Progress&)>& poll,
                       double pause_after) {
  if (passes == 0 && !(seconds > 0.0)) throw std::invalid_argument("run: give passes > 0 or seconds > 0");
  if (!(seconds >= 0.0)) throw std::invalid_argument("run: seconds must be >= 0");
  if (!(pause_after >= 0.0)) throw std::invalid_argument("run: pause_after must be >= 0");
  if (running_.exchange(true)) throw std::runtime_error("run: this renderer is already running");
  struct Done {
    std::atomic<bool>& flag;
    ~Done() { flag = false; }
  } done{running_};
  RenderStats& stats = context_.stats;
  context_.cancel = false;
  context_.paused = false;
  stats.cancelled = false;
  const auto t0 = Clock::now();
  context_.pause_due = nullptr;
  if (pause_after > 0.0) context_.pause_due = [t0, pause_after] { return since(t0) >= pause_after; };
  const uint64_t start = stats.passes;
  auto progress = [&] { return Progress{stats.passes, stats.photon.emitted, since(t0), estimator_->pass_done()}; };
  auto last_callback = Clock::now();
  const Poll inner_poll = [&]() {
    // A time limit ends the pass in progress too, once at least one pass is done.
    if (seconds > 0.0 && since(t0) >= seconds && stats.passes > start) return false;
    if (!poll || since(last_callback) < context_.settings.progress_interval) return true;
    last_callback = Clock::now();
    return poll(progress());
  };
  bool ok = prepared_ || (prepared_ = estimator_->prepare(inner_poll));
  stats.target_error_reached = false;
  while (ok && (passes == 0 || stats.passes - start < passes)) {
    if (seconds > 0.0 && since(t0) >= seconds) break;
    if ((stats.target_error_reached = target_reached())) break;
    ok = estimator_->pass(inner_poll);
    if (ok && poll && !poll(progress())) ok = false;
    last_callback = Clock::now();
  }
  if (ok && !stats.target_error_reached) stats.target_error_reached = target_reached();
  const bool timed_out = seconds > 0.0 && since(t0) >= seconds;
  stats.cancelled = !ok && !timed_out && !context_.paused;
  stats.total_seconds += since(t0);
  return stats.passes - start;
}

// Whether the image's estimated error has met settings.target_error (off at 0).
bool Renderer::target_reached() const {
  const Settings& s = context_.settings;
  if (!(s.target_error > 0.0) || !prepared_ || context_.stats.passes < static_cast<uint64_t>(s.error_min_passes) ||
      estimator_->pass_done() > 0.0)
    return false;
  return current_error().bound <= s.target_error;
}

// The image's error after the passes so far, computed once per state of the passes: the render
// loop's halting test and stats() after it ask for the same.
const ImageError& Renderer::current_error() const {
  const ErrorPasses passes = estimator_->error_passes();
  const bool same = error_cache_ && error_cache_->passes.passes == passes.passes &&
                    error_cache_->passes.ahead_end == passes.ahead_end;
  if (!same)
    error_cache_ = CachedError{passes, image_error(estimator_->errors(), passes, context_.settings.error_confidence,
                                                   estimator_->sampling_variance())};
  return error_cache_->error;
}

std::vector<float> Renderer::error_image() const {
  refuse_while_running(running_, "error()");
  const Camera& cam = context_.scene->camera();
  const int W = cam.width, H = cam.height;
  std::vector<float> out(static_cast<size_t>(W) * H * 3, 0.0f);
  if (!prepared_) return out;
  const std::vector<PixelErrorStats>& errors = estimator_->errors();
  const std::vector<float>& sampling = estimator_->sampling_variance();
  const ErrorPasses counts = estimator_->error_passes();
  StudentTByPasses t_of(context_.settings.error_confidence);
  fill_top_row_first(out, W, H, 3, [&](size_t p, float* o) {
    const uint64_t n = counts.of(p);
    write_error_channels(pixel_error(errors[p], n, t_of(n), sampling.empty() ? 0.0 : sampling[p]), o);
  });
  return out;
}

std::vector<float> Renderer::denoising_features(int samples_per_pixel, const std::function<bool()>& poll) {
  if (samples_per_pixel < 0 || samples_per_pixel > 4096)
    throw std::invalid_argument("denoising_features: samples_per_pixel must be in [0, 4096]");
  if (running_.exchange(true)) throw std::runtime_error("denoising_features: this renderer is running");
  struct Done {
    std::atomic<bool>& flag;
    ~Done() { flag = false; }
  } done{running_};
  context_.cancel = false;
  DenoisingFeatures features;
  const int spp = samples_per_pixel > 0 ? samples_per_pixel : context_.settings.samples_per_pixel;
  if (!ppm::denoising_features(context_, spp, features, poll ? poll : Poll([] { return true; }))) return {};
  const int W = width(), H = height();
  std::vector<float> out(static_cast<size_t>(W) * H * 6);
  fill_top_row_first(out, W, H, 6, [&](size_t p, float* o) {
    for (int k = 0; k < 3; ++k) o[k] = features.albedo[p][k], o[3 + k] = features.normal[p][k];
  });
  return out;
}

std::vector<float> Renderer::light_passes() const {
  refuse_while_running(running_, "light_passes()");
  if (!context_.settings.light_passes)
    throw std::runtime_error("light_passes(): make the renderer with light_passes=True");
  const int W = width(), H = height();
  std::vector<float> out(static_cast<size_t>(W) * H * 6, 0.0f);
  if (!prepared_) return out;
  fill_top_row_first(out, W, H, 6, [&](size_t p, float* o) {
    const SeenLight seen = estimator_->seen(p);
    for (int k = 0; k < 3; ++k) o[k] = saturated_float(seen.emission[k]), o[3 + k] = saturated_float(seen.environment[k]);
  });
  return out;
}

std::vector<float> Renderer::component_passes() const {
  refuse_while_running(running_, "component_passes()");
  if (!context_.settings.component_passes)
    throw std::runtime_error("component_passes(): make the renderer with component_passes=True");
  if (!estimator_->has_components())
    throw std::runtime_error("component_passes(): streamed hit points keep no light components; use stochastic "
                             "hit points or hit_point_storage='kept'");
  constexpr int kChannels = 3 * (kLightComponents + kLightClasses);
  const int W = width(), H = height();
  std::vector<float> out(static_cast<size_t>(W) * H * kChannels, 0.0f);
  if (!prepared_) return out;
  fill_top_row_first(out, W, H, kChannels, [&](size_t p, float* o) {
    const ComponentLight c = estimator_->components(p);
    for (int k = 0; k < kLightComponents; ++k)
      for (int j = 0; j < 3; ++j) *o++ = saturated_float(c.light[k][j]);
    for (int k = 0; k < kLightClasses; ++k)
      for (int j = 0; j < 3; ++j) *o++ = saturated_float(c.color[k][j]);
  });
  return out;
}

PhotonGuide Renderer::photon_guide() const {
  refuse_while_running(running_, "photon_guide()");
  return context_.photon_pass.guide();
}

std::vector<float> Renderer::image() const {
  refuse_while_running(running_, "image()");
  const Camera& cam = context_.scene->camera();
  const int W = cam.width, H = cam.height;
  std::vector<float> rgba(static_cast<size_t>(W) * H * 4, 0.0f);
  if (!prepared_) {  // black and opaque
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 1.0f;
    return rgba;
  }
  fill_top_row_first(rgba, W, H, 4, [&](size_t p, float* out) {
    const PixelValue v = estimator_->pixel(p);
    out[0] = saturated_float(v.radiance.x);
    out[1] = saturated_float(v.radiance.y);
    out[2] = saturated_float(v.radiance.z);
    out[3] = static_cast<float>(std::clamp(1.0 - v.transparency, 0.0, 1.0));  // RGB is premultiplied by it
  });
  const std::vector<float>& depth_rows = context_.depth;
  if (context_.dof_post && depth_rows.size() == static_cast<size_t>(W) * H) {
    std::vector<float> depth(depth_rows.size());
    for (int y = 0; y < H; ++y)  // to top row first, like the image
      std::copy_n(&depth_rows[static_cast<size_t>(H - 1 - y) * W], W, &depth[static_cast<size_t>(y) * W]);
    rgba = context_.settings.dof_post_preset == DofPostPreset::ReportThirds
               ? dof_post_report_thirds(rgba, depth, W, H)
               : dof_post_thin_lens(rgba, depth, cam, context_.settings.dof_max_radius);
  }
  return rgba;
}

Share Renderer::share() const {
  refuse_while_running(running_, "share()");
  const Settings& s = context_.settings;
  if (s.radius_schedule != RadiusSchedule::Global)
    throw std::runtime_error("share(): make the renderer with radius_schedule='global' (passes that merge)");
  if (context_.dof_post) throw std::runtime_error("share(): dof_mode 'post' blurs the finished image; use 'lens'");
  if (estimator_->pass_done() > 0.0)
    throw std::runtime_error("share(): a pass is in progress (paused between its bands); finish it with run()");
  if (context_.stats.passes == 0) throw std::runtime_error("share(): no pass rendered yet");
  Share out;
  out.width = width();
  out.height = height();
  out.seed = s.seed;
  out.photons_per_pass = s.photons_per_pass;
  out.alpha = s.alpha;
  out.ranges = {PassRange{s.first_pass, context_.stats.passes}};
  out.image = image();
  if (s.light_passes) out.seen = light_passes();
  const std::vector<PixelErrorStats>& errors = estimator_->errors();
  out.errors.resize(errors.size());
  for (int y = 0; y < out.height; ++y)  // to top row first, like the image
    std::copy_n(&errors[static_cast<size_t>(out.height - 1 - y) * out.width], out.width,
                &out.errors[static_cast<size_t>(y) * out.width]);
  return out;
}

RenderStats Renderer::stats() const {
  refuse_while_running(running_, "stats()");
  RenderStats s = context_.stats;
  s.photons_emitted = s.photon.emitted;
  s.photons_deposited = s.photon.deposited;
  s.radius_mean = estimator_->radius_mean();
  s.pass_done = estimator_->pass_done();
  s.memory = MemoryUse{};
  context_.add_memory(s.memory);
  estimator_->add_memory(s.memory);
  if (prepared_)
    s.error = current_error();
  return s;
}

}  // namespace ppm
