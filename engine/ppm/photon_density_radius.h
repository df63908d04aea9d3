// The initial gather radius where a pass's photons, not the pixels, are the limit.
//
// The eye pass starts every hit point at a few pixel footprints. Through a long
// lens or a small orthographic window that is far below the spacing of one
// pass's photons, so hit points gather none for many passes and their
// indirect light is missing or blotchy (a closed sphere through a 5000 mm
// lens after 30 passes: median pixel half the analytic radiance, peaks 14
// times it). So the initial radius is at least the photons' own spacing: the
// median distance from a photon of one pass to its kSpacingNeighbours-th
// nearest neighbour in that pass. It is measured once, on a pilot of an eighth
// of a pass traced with its own random stream (the image's photons are the same
// as without it), and scaled to a whole pass.
//
// One radius for the whole scene, from where photons are, rather than a search
// around each hit point: around a hit point that photons never reach (the
// ground beside a closed, lit box) a search finds photons only behind some
// other surface, and gathering them leaks light through it.
#pragma once

#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <atomic>
#include <cstdint>
#include <functional>

namespace ppm {

constexpr int kSpacingNeighbours = 4;  // photons of one pass a hit point holds at least, at the median density
// In media the nearest: a ball of that radius holds ln 2 photons a pass at the median density.
// Four (as on surfaces) made a dense slab's lit face 5% dark: the floor exceeded the footprints
// there, and the balls reached further out of the medium.
constexpr int kVolumeSpacingNeighbours = 1;
constexpr int kSpacingSamples = 1024;  // photons whose neighbours are measured

struct PhotonSpacing {
  double radius = 0.0;   // 0: the pilot pass deposited too few photons to tell
  uint64_t photons = 0;  // deposited by the pilot pass
  // Scenes with media: the same for its volume photons, in 3-D (the floor of a hit point's radius
  // in a medium; without it, fog the camera is inside flares: see stochastic_hit_points.h).
  double volume_radius = 0.0;
  uint64_t volume_photons = 0;
  double seconds = 0.0;
};

// Measures the spacing (see above); `start_radius` (> 0) is where the neighbour search begins.
// Returns false if cancelled.
bool measure_photon_spacing(const Scene& scene, const LightSampler& lights, const Settings& settings, int threads,
                            double start_radius, std::atomic<bool>& cancel, const std::function<bool()>& poll,
                            PhotonSpacing& out);

}  // namespace ppm
