// The render loop, as in the paper:
//   hit_points = eye_pass(scene, camera)
//   index      = grid over hit points (or over each pass's photons)
//   for each pass until done, out of time or cancelled:
//       direct_light_pass(hit_points)              // light sampling, running mean
//       photons_emitted += photon_pass(index, hit_points)
//       progressive_update(hit_points, alpha, P)   // cross-generation rule
//   image = emitted + direct + tau / (pi r^2 N_emitted)
// A pass cancelled half-way is discarded, so the image always reflects whole passes.
#pragma once

#include "ppm/eye_pass.h"
#include "ppm/hit_point.h"
#include "ppm/photon_pass.h"
#include "ppm/pixel_stats.h"
#include "ppm/scene_analysis.h"
#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ppm {

struct Progress {
  uint64_t passes;
  uint64_t photons_emitted;
  double seconds;  // since this run() started
};

struct RenderStats {
  uint64_t passes = 0;
  uint64_t photons_emitted = 0;
  uint64_t photons_deposited = 0;
  uint64_t hit_points = 0;
  uint64_t direct_samples = 0;  // direct-light samples per hit point so far
  double eye_seconds = 0, direct_seconds = 0, update_seconds = 0, total_seconds = 0;
  PhotonPassCounters photon;
  bool cancelled = false;
  size_t memory_bytes = 0;
  int threads = 1;
  double initial_radius_mean = 0.0;
  double photon_spacing = 0.0;  // floor of the automatic initial radius (photon_density_radius.h); 0 if none
  uint64_t radii_widened = 0;   // hit points (fixed) or pixels (stochastic) whose initial radius it raised
  double density_radius_seconds = 0.0;
  double radius_mean = 0.0;
  std::vector<std::string> skipped;
};

class Renderer {
 public:
  // The scene must stay alive and unchanged while the renderer exists.
  Renderer(std::shared_ptr<const Scene> scene, const Settings& settings);

  // Runs up to `passes` passes (0 = no limit) and for at most `seconds`
  // (0 = no limit; at least one of the two must be set). `poll` is called
  // between passes and every settings.progress_interval inside them; returning
  // false cancels (the unfinished pass is dropped). Returns the passes completed.
  uint64_t run(uint64_t passes, double seconds, const std::function<bool(const Progress&)>& poll);

  // Thread-safe: stops the current run within one poll interval.
  void cancel() { cancel_ = true; }

  // Linear RGBA, rows from the top of the image, alpha = 1. Like stats(), it
  // throws std::runtime_error if called while run() is in progress (from the
  // progress callback or another thread): the passes are writing the data.
  std::vector<float> image() const;
  RenderStats stats() const;
  const Settings& settings() const { return settings_; }
  int width() const { return scene_->camera().width; }
  int height() const { return scene_->camera().height; }
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;
  const HitPoints& hit_points() const { return hit_points_; }

 private:
  bool ensure_eye_pass(const std::function<bool()>& poll);
  bool measure_photon_spacing_once(const HitPoints& hp, const std::function<bool()>& poll);
  bool one_pass(const std::function<bool()>& poll);        // fixed hit points (PPM)
  bool stochastic_pass(const std::function<bool()>& poll); // new hit points every pass (SPPM)
  void decide_depth_of_field();
  EyePassOptions eye_options(uint64_t generation) const;

  std::shared_ptr<const Scene> scene_;
  Settings settings_;
  int threads_;
  LightSampler lights_;
  SceneAnalysis analysis_;
  HitPoints hit_points_;              // fixed: the render's; stochastic: the latest pass's
  HitPoints spare_hit_points_;        // stochastic: the pass being made
  std::vector<PixelStats> pixels_;    // stochastic only
  std::vector<float> depth_;          // per pixel, bottom row first like the eye pass (POST only)
  bool dof_post_ = false, dof_lens_ = false;
  PhotonPass photon_pass_;
  std::vector<Color> direct_sums_;  // direct_light_pass scratch, kept across passes
  bool eye_done_ = false;
  bool spacing_measured_ = false;
  double min_initial_r2_ = 0.0;  // the photons' spacing squared: a floor for automatic initial radii
  std::atomic<bool> cancel_{false};
  std::atomic<bool> running_{false};  // image()/stats() refuse to read while a pass writes
  RenderStats stats_;
};

}  // namespace ppm
