// The photons' spacing, a floor for the initial radius (see photon_density_radius.h).
#include "ppm/photon_density_radius.h"

#include "base/parallel.h"
#include "ppm/photon_tracer.h"
#include "ppm/photon_tracer_media.h"
#include "ppm/quantile_grid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace ppm {
namespace {

constexpr uint64_t kPilotStream = 3ull << 40;  // apart from the eye (1) and photon (2 << 40 + pass) streams
constexpr size_t kPhotonChunk = 1024;
constexpr int kMaxDoublings = 60;  // from the start radius to any scene that fits in doubles
// The pilot traces 1/kPilotFraction of a pass (at least kMinPilotPhotons): spacing goes as
// 1/sqrt(density), so a full pass's is the pilot's divided by sqrt(pass / pilot).
constexpr uint64_t kPilotFraction = 8;
constexpr uint64_t kMinPilotPhotons = 8192;

uint64_t pilot_photons(const Settings& settings) {
  return std::min(settings.photons_per_pass, std::max(settings.photons_per_pass / kPilotFraction, kMinPilotPhotons));
}

// The positions of the pilot's photons, in photon order (the same for any thread count): on
// surfaces, and (scenes with media, traced through them) in media.
bool trace_pilot(const Scene& scene, const LightSampler& lights, const Settings& settings, int threads,
                 std::atomic<bool>& cancel, const std::function<bool()>& poll, std::vector<Vec3>& positions,
                 std::vector<Vec3>& volume_positions) {
  const uint64_t photons = pilot_photons(settings);
  const size_t chunks = (photons + kPhotonChunk - 1) / kPhotonChunk;
  std::vector<std::vector<Vec3>> buffers(chunks), volume_buffers(chunks);
  const BounceLimits limits = BounceLimits::of(settings, scene);
  auto trace = [&](int, size_t c) {
    const uint64_t first = c * kPhotonChunk, last = std::min<uint64_t>(photons, (c + 1) * kPhotonChunk);
    auto rng_of = [&](uint64_t i) { return Rng(settings.seed, kPilotStream, i); };
    auto deposit = [&](const Vec3& pos, const Vec3&, const Vec3&, const Color&, const Bounces&, PhotonTag) {
      buffers[c].push_back(pos);
    };
    if (!scene.has_media()) {
      trace_photons(scene, lights, settings, limits, first, last, rng_of, deposit);
      return;
    }
    trace_photons_in_media(scene, lights, settings, limits, first, last, rng_of, deposit,
                           [&](const Vec3& pos, const Vec3&, const Color&, const Bounces&, bool) {
                             volume_buffers[c].push_back(pos);
                           },
                           [](const PhotonBeam&) {});
  };
  if (!parallel_chunks(threads, chunks, trace, cancel, poll, settings.progress_interval)) return false;
  for (const std::vector<Vec3>& b : buffers) positions.insert(positions.end(), b.begin(), b.end());
  for (const std::vector<Vec3>& b : volume_buffers) volume_positions.insert(volume_positions.end(), b.begin(), b.end());
  return true;
}

// Distance from photon `self` to its k-th nearest other photon (inf if there are not k others).
double kth_neighbour_distance(const QuantileGrid& grid, const std::vector<Vec3>& positions, uint32_t self, int k,
                              double r, std::vector<double>& d2) {
  const Vec3 p = positions[self];
  for (int doubling = 0; doubling <= kMaxDoublings; ++doubling, r *= 2.0) {
    d2.clear();
    const double r2 = r * r;
    grid.for_each_candidate_in_box(p - r, p + r, [&](uint32_t j) {
      const Vec3 d = positions[j] - p;
      const double dd = glm::dot(d, d);
      if (j != self && dd <= r2) d2.push_back(dd);
    });
    if (d2.size() >= static_cast<size_t>(k)) {
      std::nth_element(d2.begin(), d2.begin() + (k - 1), d2.end());
      return std::sqrt(d2[k - 1]);
    }
  }
  return kInf;
}

// The median over photons at evenly spaced places in the pilot (so the sample follows where photons
// land) of the distance to their k-th neighbour, scaled to a whole pass: spacing goes as
// density^(-1/dimensions). 0 if the pilot has too few photons to tell.
double median_spacing(const std::vector<Vec3>& positions, int k, int dimensions, const Settings& settings,
                      int threads, double start_radius) {
  if (positions.size() <= static_cast<size_t>(k)) return 0.0;
  QuantileGrid grid;
  grid.build(positions, {}, threads);
  const size_t samples = std::min<size_t>(kSpacingSamples, positions.size());
  std::vector<double> distances(samples);
  parallel_for(threads, samples, [&](size_t begin, size_t end) {
    std::vector<double> d2;
    for (size_t s = begin; s < end; ++s) {
      const auto self = static_cast<uint32_t>(s * positions.size() / samples);
      distances[s] = kth_neighbour_distance(grid, positions, self, k, start_radius, d2);
    }
  });
  std::nth_element(distances.begin(), distances.begin() + samples / 2, distances.end());
  const double median = distances[samples / 2];
  const double to_a_pass =
      std::pow(static_cast<double>(pilot_photons(settings)) / settings.photons_per_pass, 1.0 / dimensions);
  return std::isfinite(median) ? median * to_a_pass : 0.0;
}

}  // namespace

bool measure_photon_spacing(const Scene& scene, const LightSampler& lights, const Settings& settings, int threads,
                            double start_radius, std::atomic<bool>& cancel, const std::function<bool()>& poll,
                            PhotonSpacing& out) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Vec3> positions, volume_positions;
  if (!trace_pilot(scene, lights, settings, threads, cancel, poll, positions, volume_positions)) return false;
  out.photons = positions.size();
  out.volume_photons = volume_positions.size();
  out.radius = median_spacing(positions, kSpacingNeighbours, 2, settings, threads, start_radius);
  out.volume_radius = median_spacing(volume_positions, kVolumeSpacingNeighbours, 3, settings, threads, start_radius);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return true;
}

}  // namespace ppm
