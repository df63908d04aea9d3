// What a render reports: progress to its callback while it runs, and its
// statistics (Renderer::stats()) between runs.
#pragma once

#include "ppm/error_estimate.h"
#include "ppm/photon_pass.h"

#include <cstdint>
#include <string>
#include <vector>

namespace ppm {

struct Progress {
  uint64_t passes;
  uint64_t photons_emitted;
  double seconds;    // since this run() started
  double pass_done;  // the share of the pass in progress that is kept whatever happens (its bands)
};

// Bytes each part of a render holds (capacities: what it has allocated).
struct MemoryUse {
  size_t scene = 0;       // geometry, BVH, textures, materials, lights (shared by the scene's renders)
  size_t hit_points = 0;  // the hit points (stochastic: one band's), and what a pass keeps per hit point
  size_t pixels = 0;      // per-pixel statistics and buffers
  size_t photons = 0;     // one pass's photons
  size_t index = 0;       // the spatial index over photons or hit points
  size_t total() const { return scene + hit_points + pixels + photons + index; }
};

struct RenderStats {
  uint64_t passes = 0;
  uint64_t photons_emitted = 0;
  uint64_t photons_deposited = 0;
  uint64_t hit_points = 0;
  std::string hit_point_storage;  // fixed hit points: "kept" or "streamed"; stochastic: ""
  uint64_t direct_samples = 0;  // direct-light samples per hit point so far
  double eye_seconds = 0, direct_seconds = 0, update_seconds = 0, total_seconds = 0;
  PhotonPassCounters photon;
  bool cancelled = false;
  MemoryUse memory;
  int threads = 1;
  double initial_radius_mean = 0.0;
  double photon_spacing = 0.0;  // floor of the automatic initial radius (photon_density_radius.h); 0 if none
  double volume_photon_spacing = 0.0;  // the same in media
  uint64_t radii_widened = 0;   // hit points (fixed) or pixels (stochastic) whose initial radius it raised
  double density_radius_seconds = 0.0;
  double radius_mean = 0.0;
  double pass_done = 0.0;  // the share of the pass in progress already in the image (Progress::pass_done)
  std::vector<std::string> skipped;
  ImageError error;                  // the image's estimated error (error_estimate.h)
  bool target_error_reached = false;  // the last run() stopped on settings.target_error
};

}  // namespace ppm
