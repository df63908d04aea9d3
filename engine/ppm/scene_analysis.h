// Looks at a built scene once and decides which work the render can skip.
// Every skip is named in `skipped` and reported by Renderer::stats().
#pragma once

#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace ppm {

struct SceneAnalysis {
  bool follow_specular = true;      // eye pass follows mirror/glass chains
  bool trace_photons = true;        // photon passes can add anything
  bool resample_direct = true;      // direct light needs a new sample every pass
  bool sample_direct = true;        // direct light sampled at all
  std::vector<std::string> skipped;
};

SceneAnalysis analyse_scene(const Scene& scene, const LightSampler& lights, const Settings& settings);

}  // namespace ppm
