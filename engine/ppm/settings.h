// Render settings: one struct with documented defaults. settings_table.h names them for front ends
// (the Python binding builds Settings from keyword arguments through it and rejects unknown names).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

namespace ppm {

enum class DirectLight : uint8_t {
  Sampled,  // direct light by light sampling with shadow rays; photons carry indirect light and caustics
  Photons,  // the reference design: photons carry all light
};
// How eye paths take the light a lobe they follow reflects (rough ones: EyeTracer::sample_lights).
enum class FollowedLight : uint8_t {
  Mis,     // light sampling and the lobe's own draw, weighed by the balance heuristic
  Lights,  // light sampling alone, where a light has a density (the draw's meetings count nothing)
  Draws,   // the draw alone (lights of no size go unseen): to test the other two against
};
enum class GatherOrganisation : uint8_t {
  HitPoints,  // hit points in the grid, each photon queries it
  Photons,    // each pass's photons in the grid, each hit point queries it
};
enum class GridKind : uint8_t { Quantile, Hash };
enum class HitPointMode : uint8_t {
  Fixed,       // PPM: one eye pass, hit points kept for the whole render
  Stochastic,  // SPPM (Hachisuka & Jensen 2009): new eye samples every pass, statistics kept per pixel
};
// Where fixed hit points live between passes (streamed_hit_points.h).
enum class HitPointStorage : uint8_t {
  Auto,      // kept where the machine's available memory holds them, streamed otherwise
  Kept,      // every hit point kept for the whole render (about 360 bytes each)
  Streamed,  // made again band by band each pass; 48 bytes of statistics kept per hit point
};
// How stochastic hit points' gather radius shrinks over passes.
enum class RadiusSchedule : uint8_t {
  Progressive,  // per pixel, from its photon counts, with the cross-generation threshold (progressive.h)
  Global,       // a factor of the pass index alone (radius_schedule.h): passes render apart and merge (share.h)
};
enum class DofMode : uint8_t { Off, Post, Lens };
enum class DofPostPreset : uint8_t {
  ThinLens,      // circle of confusion from the thin-lens equation, depth-aware gather
  ReportThirds,  // the 2019 report: nearest third of pixels 5x5 box, middle third 3x3
};

struct Settings {
  uint64_t photons_per_pass = 200000;
  double alpha = 0.7;               // radius reduction (Hachisuka 2008)
  uint32_t threshold = 30;          // P of the cross-generation rule; 1 = classic PPM (bench/run.py threshold_scenes)
  int max_bounces = 12;             // photon path length and eye specular chain length
  // Cycles' Light Paths limits, honoured when light_path_limits is on (bounce_limits.h): a full
  // camera-to-light path then continues from at most total_bounces scatterings, of which at most
  // diffuse_bounces diffuse, ..., volume_bounces in media (Cycles' defaults). Photon paths and eye
  // chains are then as long as total_bounces allows, and max_bounces is not used.
  bool light_path_limits = false;
  int total_bounces = 12;
  int diffuse_bounces = 4;
  int glossy_bounces = 4;
  int transmission_bounces = 12;
  int volume_bounces = 0;  // scatterings in media a path continues from (Cycles' default 0)
  int samples_per_pixel = 4;        // jittered eye samples per pixel (fixed hit points)
  uint64_t seed = 0;
  int threads = 0;                  // 0 = all cores
  double initial_radius = 0.0;      // metres; 0 = automatic from the pixel footprint
  double initial_radius_pixels = 2.0;  // automatic radius, in pixels at the hit point's distance
  double volume_radius_scale = 1.0;    // hit points in media: their automatic initial radius, times the surface's
  bool volume_beams = false;           // photon beams and split camera paths in homogeneous media (the add-on: on)
  bool volume_boundary = true;         // hit points in media: count the gather ball inside the nearest surface only
  bool density_radius = true;       // automatic radius also widened to the photon density (photon_density_radius.h)
  DirectLight direct_light = DirectLight::Sampled;
  FollowedLight followed_light = FollowedLight::Mis;
  GatherOrganisation gather = GatherOrganisation::Photons;  // measured faster: bench/run.py throughput
  GridKind grid = GridKind::Quantile;
  double progress_interval = 0.1;   // seconds between progress callbacks inside a pass
  HitPointMode hit_points = HitPointMode::Fixed;
  HitPointStorage hit_point_storage = HitPointStorage::Auto;  // fixed hit points only
  DofMode dof_mode = DofMode::Off;
  DofPostPreset dof_post_preset = DofPostPreset::ThinLens;
  int dof_max_radius = 32;          // POST: largest blur radius in pixels
  bool scene_analysis = true;       // false: do all the work even where the scene cannot use it (benchmarks)
  // Alpha as Cycles' Film > Transparent: camera rays that escape leave the pixel transparent (alpha 0)
  // instead of showing the background; with transparent_glass also those that escape through smooth glass.
  bool transparent_background = false;
  bool transparent_glass = false;
  // Halting on the error estimate (error_estimate.h): run() stops once the image's estimated
  // relative error, at `error_confidence`, is at most target_error (0: off), after at least
  // error_min_passes passes.
  double target_error = 0.0;
  double error_confidence = 0.95;
  int error_min_passes = 8;
  // Stochastic hit points: up to this many eye samples a pixel each pass, where the error estimate
  // finds the pixel's pass values noisiest (adaptive_samples.h); 1: one everywhere.
  int adaptive_samples = 1;
  // Keep what camera rays see at no bounce, emission and world apart (Renderer::light_passes,
  // Cycles' Emit and Env passes): 24 bytes a pixel more with stochastic hit points.
  bool light_passes = false;
  // Keep the light apart by Cycles' Diffuse, Glossy, Transmission and Volume Direct and Indirect,
  // the Color passes and the caustic part (light_components.h, Renderer::component_passes): 134
  // bytes more per fixed hit point kept, 240 a pixel with stochastic hit points (and 96 more in
  // scenes with media), and 120 per hit point of a pass's scratch (its direct light and photons
  // by class).
  bool component_passes = false;
  // Guide point, sphere, spot (of a radius) and area lights' photons towards where the error
  // estimate finds the image noisiest (photon_guide.h).
  bool photon_guiding = false;
  // Stochastic hit points: the radius schedule, and the index of the first pass this renderer
  // renders (0 for the first). Rendering a share of a still's passes (share.h) takes the global
  // schedule; the random numbers of pass i are then those of pass i of one long render.
  RadiusSchedule radius_schedule = RadiusSchedule::Progressive;
  uint64_t first_pass = 0;

  // Scatterings a photon path or an eye chain may take.
  int path_bounces() const { return light_path_limits ? std::min(total_bounces, 1000) + 1 : max_bounces; }

  // Throws std::invalid_argument naming the setting when a value is out of range.
  void validate() const;
};

}  // namespace ppm
