// Range checks for the render settings.
#include "ppm/settings.h"

#include <cmath>
#include <stdexcept>

namespace ppm {

void Settings::validate() const {
  auto fail = [](const std::string& m) { throw std::invalid_argument("settings: " + m); };
  if (photons_per_pass == 0) fail("photons_per_pass must be at least 1");
  if (photons_per_pass > (1ull << 32)) fail("photons_per_pass must be below 2^32");
  if (!(alpha > 0.0 && alpha < 1.0)) fail("alpha must be in (0, 1)");
  if (threshold == 0) fail("threshold must be at least 1");
  if (max_bounces < 1 || max_bounces > 1000) fail("max_bounces must be in [1, 1000]");
  for (int limit : {total_bounces, diffuse_bounces, glossy_bounces, transmission_bounces, volume_bounces})
    if (limit < 0 || limit > 1024) fail("total, diffuse, glossy, transmission and volume bounces must be in [0, 1024]");
  if (samples_per_pixel < 1 || samples_per_pixel > 4096) fail("samples_per_pixel must be in [1, 4096]");
  if (threads < 0 || threads > 1024) fail("threads must be in [0, 1024]");
  if (!(initial_radius >= 0.0) || !std::isfinite(initial_radius)) fail("initial_radius must be >= 0");
  if (!(initial_radius_pixels > 0.0) || !std::isfinite(initial_radius_pixels))
    fail("initial_radius_pixels must be positive");
  if (!(volume_radius_scale > 0.0) || !std::isfinite(volume_radius_scale)) fail("volume_radius_scale must be positive");
  if (dof_max_radius < 1 || dof_max_radius > 256) fail("dof_max_radius must be in [1, 256]");
  if (!(progress_interval > 0.0) || !std::isfinite(progress_interval)) fail("progress_interval must be positive");
  if (!(target_error >= 0.0) || !std::isfinite(target_error)) fail("target_error must be >= 0 (0: off)");
  if (!(error_confidence > 0.0 && error_confidence < 1.0)) fail("error_confidence must be in (0, 1)");
  if (error_min_passes < 2 || error_min_passes > 1000000) fail("error_min_passes must be in [2, 1000000]");
  if (radius_schedule == RadiusSchedule::Global && hit_points != HitPointMode::Stochastic)
    fail("radius_schedule 'global' needs hit_points 'stochastic'");
  if (first_pass > 0 && radius_schedule != RadiusSchedule::Global)
    fail("first_pass > 0 (a share of a still's passes) needs radius_schedule 'global'");
  if (first_pass > (1ull << 40)) fail("first_pass must be below 2^40");
  if (component_passes && direct_light != DirectLight::Sampled)
    fail("component_passes needs direct_light 'sampled' (Direct is the light sampled at the first surface)");
  if (component_passes && gather != GatherOrganisation::Photons)
    fail("component_passes needs gather 'photons'");
  if (photon_guiding && gather != GatherOrganisation::Photons) fail("photon_guiding needs gather 'photons'");
  if (photon_guiding && radius_schedule == RadiusSchedule::Global)
    fail("photon_guiding ties each pass to the ones before; radius_schedule 'global' needs passes apart");
  if (adaptive_samples < 1 || adaptive_samples > 64) fail("adaptive_samples must be in [1, 64]");
}

}  // namespace ppm
