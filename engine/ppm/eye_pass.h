// The eye pass: trace N jittered samples per pixel through mirror and glass
// chains (splitting at glass with the Fresnel weights for the first few
// interfaces) and record a hit point at the first non-specular surface.
// Emission and background met on the way go straight into the pixel.
#pragma once

#include "ppm/hit_point.h"
#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <atomic>
#include <functional>

namespace ppm {

struct EyePassOptions {
  int threads = 1;
  bool follow_specular = true;  // false when the scene has no specular surface (skip the branching)
  int samples_per_pixel = 4;
  uint64_t generation = 0;      // stochastic PPM draws new eye samples every pass
  bool lens = false;            // sample the aperture (thin lens)
  bool record_depth = false;    // per-pixel depth for the depth-of-field post-process
  bool record_features = false; // per-pixel denoising albedo and normal (HitPoints::albedo)
  bool record_samples = false;  // each hit point's eye sample, each sample's light (HitPoints::sample_light)
  bool record_seen = false;     // per pixel, the emission and world seen at no bounce (HitPoints::seen)
  bool record_components = false;  // light components (HitPoints::route, components, pixel_components)
  // Free each chunk of the scratch once it is joined into `out`, for a single eye pass whose scratch
  // is not kept: the chunks and `out` then never both hold every hit point.
  bool release_chunks = false;
  // Optional, per pixel of the image (row 0 at the bottom): its own number of samples, at most
  // samples_per_pixel (the random streams' stride); nullptr: samples_per_pixel everywhere.
  const uint8_t* pixel_samples = nullptr;
  // The rows traced: [row_begin, row_end), row 0 at the bottom; row_end < 0 means to the top.
  // The per-pixel outputs (pixel_begin, emitted, transparency, depth) cover these rows only,
  // indexed from the first pixel of row_begin.
  int row_begin = 0;
  int row_end = -1;
  // The renderer's lights: split camera paths in fog aim half their scatterings at one with a place
  // (EyeTracer::split_path); nullptr: they do not.
  const LightSampler* lights = nullptr;
};

// What the eye pass's chunks of rows record before they are joined into `out`, kept by the
// caller across passes: allocated anew for every band of stochastic hit points, their pages
// were zeroed by the kernel each time (a third of a 1080p pass went to it).
struct EyePassScratch {
  struct Chunk {
    std::vector<HitPoint> points;
    std::vector<HitPointShading> shading;
    std::vector<Bounces> chain;  // with bounce limits
    std::vector<uint16_t> sample;  // with record_samples
    std::vector<uint8_t> route;    // with record_components
    std::vector<MediumStack> media;       // scenes with media: each hit point's
    std::vector<VolumeHitPoint> volume;   // scenes with media: the hit points in media
    std::vector<VolumeBeam> beams;        // ... and beams (Settings::volume_beams)
  };
  std::vector<Chunk> chunks;
  std::vector<uint32_t> counts;  // hit points per pixel
  size_t memory_bytes() const;
};

// Returns false if cancelled; `out` is then incomplete. A band of rows traces the same random
// samples as those rows of the whole image.
bool eye_pass(const Scene& scene, const Settings& settings, const EyePassOptions& options, HitPoints& out,
              EyePassScratch& scratch, std::atomic<bool>& cancel, const std::function<bool()>& poll);

}  // namespace ppm
