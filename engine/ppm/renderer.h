// The render loop, as in the papers (Hachisuka et al. 2008; with stochastic
// hit points Hachisuka & Jensen 2009, where every pass starts with its own
// eye pass and the statistics live per pixel):
//   hit_points = eye_pass(scene, camera)                    // Estimator::prepare
//   for each pass until done, out of time or cancelled:     // Estimator::pass
//       photon_pass(hit_points)        // into each hit point's pending m, tau_m
//       direct_light_pass(hit_points)  // light sampling, running sum
//       progressive_update(hit_points, alpha, P)  // cross-generation rule: fold
//                                                 // m, tau_m into r, n, tau once m >= P
//   image = emitted + direct / samples + (tau + tau_m) / (pi r^2 N_emitted)
// A cancelled pass leaves the image as it was before it (fixed hit points), or
// keeps the bands of rows it completed and resumes at the next (stochastic).
#pragma once

#include "ppm/estimator.h"
#include "ppm/render_context.h"
#include "ppm/render_stats.h"
#include "ppm/settings.h"
#include "ppm/share.h"
#include "scene/scene.h"

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace ppm {

class Renderer {
 public:
  // The scene must stay alive and unchanged while the renderer exists.
  Renderer(std::shared_ptr<const Scene> scene, const Settings& settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Runs up to `passes` passes (0 = no limit) and for at most `seconds`
  // (0 = no limit; at least one of the two must be set). `poll` is called
  // between passes and every settings.progress_interval inside them; returning
  // false cancels (what becomes of the unfinished pass: above). With `pause_after` > 0, a
  // stochastic pass still in progress that long after the start returns at the end of its band,
  // its finished bands in the image, and the next run() continues it (an interactive view shows
  // new pixels several times a pass). Returns the passes completed.
  uint64_t run(uint64_t passes, double seconds, const std::function<bool(const Progress&)>& poll,
               double pause_after = 0.0);

  // Thread-safe: stops the current run within one poll interval.
  void cancel() { context_.cancel = true; }

  // Linear RGBA, rows from the top of the image, RGB premultiplied by alpha.
  // Like stats(), it throws std::runtime_error if called while run() is in
  // progress (from the progress callback or another thread): the passes are
  // writing the data.
  std::vector<float> image() const;
  RenderStats stats() const;
  // Per pixel, rows from the top like image(): the estimated bias and noise (at the settings'
  // confidence) of its luminance, and its luminance (error_estimate.h); 3 floats a pixel. Before
  // two passes the noise is inf.
  std::vector<float> error_image() const;
  // Cycles' Denoising Albedo and Denoising Normal (denoising_features.h) from `samples_per_pixel`
  // eye samples per pixel (0: the settings'), rows from the top: 6 floats a pixel, albedo RGB and
  // the world-space normal. An eye pass of its own, made band by band; `poll` returning false
  // cancels it (then it returns an empty vector). Not while run() is in progress.
  std::vector<float> denoising_features(int samples_per_pixel, const std::function<bool()>& poll);
  // With settings.light_passes: per pixel, rows from the top, what camera rays see at no bounce,
  // emission of surfaces and lights (Cycles' Emit) and the world (Env): 6 floats a pixel.
  std::vector<float> light_passes() const;
  // With settings.component_passes: per pixel, rows from the top, the light by component
  // (light_components.h) in LightComponent order, then the Diffuse, Glossy and Transmission Color:
  // 30 floats a pixel. The light is each component's radiance: the six Direct and Indirect ones,
  // Emit and Env add up to the image before a POST depth-of-field blur (the caustic part is within
  // the Indirect ones).
  std::vector<float> component_passes() const;
  // The passes rendered so far as a share of a still (share.h), to merge with other machines'.
  // Needs radius_schedule 'global', whole passes (not between the bands of one) and no POST depth of
  // field (it blurs the finished image, not a pass).
  Share share() const;
  const Settings& settings() const { return context_.settings; }
  // With settings.photon_guiding: what the guide has learned (photon_guide.h).
  PhotonGuide photon_guide() const;
  int width() const { return context_.scene->camera().width; }
  int height() const { return context_.scene->camera().height; }

 private:
  RenderContext context_;
  std::unique_ptr<Estimator> estimator_;
  bool target_reached() const;
  const ImageError& current_error() const;

  struct CachedError {
    ErrorPasses passes;
    ImageError error;
  };
  mutable std::optional<CachedError> error_cache_;  // current_error()'s, for the passes it was made at

  bool prepared_ = false;             // Estimator::prepare has completed
  std::atomic<bool> running_{false};  // image()/stats() refuse to read while a pass writes
};

// A renderer of `scene` as a front end makes one: the scene built first (BVH, lights) and its
// emitters checked against the settings' path length (Scene::check_energy_range).
std::unique_ptr<Renderer> make_renderer(const std::shared_ptr<Scene>& scene, const Settings& settings);

}  // namespace ppm
