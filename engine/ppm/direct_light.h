// Direct light at the hit points by light sampling with shadow rays: each
// call adds one sample per analytic light and one emissive triangle (chosen by
// flux) to every hit point's running sum. Called once per pass, or once in
// all when every light is a delta light (the sample is then exact).
#pragma once

#include "ppm/hit_point.h"
#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <atomic>
#include <functional>
#include <vector>

namespace ppm {

// A pass's sums per hit point until the pass completes (a cancelled pass adds nothing); the caller
// keeps them across passes so that no pass allocates. With light components (the hit points'
// `components`), the sums by class of lobe as well.
struct DirectScratch {
  std::vector<Color> sums;
  std::vector<ClassColors> classes;
  size_t memory_bytes() const { return sums.capacity() * sizeof(Color) + classes.capacity() * sizeof(ClassColors); }
};

// Hit point i draws the random numbers of index `first_index + i` of the pass,
// so that the bands of one pass (stochastic hit points) draw distinct ones.
bool direct_light_pass(const Scene& scene, const LightSampler& lights, const Settings& settings,
                       uint64_t pass, int threads, HitPoints& hit_points, DirectScratch& scratch,
                       std::atomic<bool>& cancel, const std::function<bool()>& poll, uint64_t first_index = 0);

// Scenes with media: direct light at the hit points in media (`points[i].direct`), one sample per
// analytic light (the world: about the eye direction and against it) and one emissive triangle,
// through the phase function and the media's transmittance (Scene::shadow_transmittance).
bool volume_direct_light_pass(const Scene& scene, const LightSampler& lights, const Settings& settings, uint64_t pass,
                              int threads, std::vector<VolumeHitPoint>& points, std::atomic<bool>& cancel,
                              const std::function<bool()>& poll, uint64_t first_index = 0);

}  // namespace ppm
