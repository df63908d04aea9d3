// Scene analysis (see scene_analysis.h).
#include "ppm/scene_analysis.h"

namespace ppm {

SceneAnalysis analyse_scene(const Scene& scene, const LightSampler& lights, const Settings& settings) {
  SceneAnalysis a;
  a.sample_direct = settings.direct_light == DirectLight::Sampled && !lights.empty();
  a.trace_photons = !lights.empty();  // not a skip: there is nothing to emit from
  a.skipped = scene.light_notes();     // emitting media that cannot emit photons: facts, not choices
  if (!settings.scene_analysis) return a;  // everything else on, for measuring what the skips save
  bool any_specular = false, any_receiver = false, any_scatter = false;
  size_t mixtures = 0;
  for (const Material& m : scene.materials()) {
    mixtures += m.kind == MaterialKind::Mixture ? 1 : 0;
    any_specular |= has_followed(m);
    if (!is_specular(m) && !is_black(m)) any_receiver = true;
    if (!is_black(m) && max_component(m.base_color) > 0.0) any_scatter = true;
  }
  for (const Medium& m : scene.media())  // photons scatter in media and hit points gather there
    if (m.scatters()) any_receiver = any_scatter = true;
  if (mixtures == 0 && !scene.materials().empty())
    a.skipped.push_back("mixture lobes: every material is a single kind (the direct BSDF paths)");
  if (!any_specular) {
    a.follow_specular = false;
    a.skipped.push_back("eye specular chains: no mirror or glass material");
  }
  if (lights.dropped() > 0)
    a.skipped.push_back("zero-power lights: " + std::to_string(lights.dropped()) + " left out of sampling");
  // Emitting media's direct light is by photons whatever the setting (no light sampling reaches them).
  const bool photons_direct = settings.direct_light == DirectLight::Photons || lights.has_emitting_media();
  // With direct light sampled, photons only matter after a bounce off something that scatters.
  if (lights.empty() || !any_receiver || (!photons_direct && !any_scatter)) {
    a.trace_photons = false;
    a.skipped.push_back("photon passes: no light can reach a diffuse or glossy surface");
  }
  a.sample_direct = settings.direct_light == DirectLight::Sampled && !lights.empty();
  bool all_delta = true;
  for (uint32_t l : lights.analytic()) all_delta &= light_is_delta(scene.lights()[l]);
  all_delta &= !lights.has_triangles();
  // Stochastic hit points are new every pass and need a new direct sample each time.
  if (a.sample_direct && all_delta && settings.hit_points == HitPointMode::Fixed) {
    a.resample_direct = false;
    a.skipped.push_back("direct light resampling: only point, spot and hard sun lights (one exact sample)");
  }
  return a;
}

}  // namespace ppm
