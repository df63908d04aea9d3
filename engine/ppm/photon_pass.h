// A photon pass: trace `photons_per_pass` photons in parallel and gather them
// into the hit points' pending statistics (m, tau_m), and what the pass alone found into their
// pass_flux and pass_bias (for the error estimate, error_estimate.h). Two organisations, both
// over either spatial index (quantile grid or hashed grid):
//   HitPoints: the index holds the hit points as spheres; every photon looks up
//     the hit points around it and adds to one accumulator per block of
//     photons (as many blocks as threads), summed in block order after the
//     pass (no locks, deterministic);
//   Photons:   the pass's photons are stored in the index's cell order and
//     every hit point gathers the photons inside its radius (the default: no
//     scattered writes).
#pragma once

#include "ppm/bounce_limits.h"
#include "ppm/hash_grid.h"
#include "ppm/hit_point.h"
#include "ppm/photon_beams.h"
#include "ppm/photon_guide.h"
#include "ppm/quantile_grid.h"
#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <atomic>
#include <functional>

namespace ppm {

struct PhotonPassCounters {
  uint64_t emitted = 0;
  uint64_t deposited = 0;
  double trace_seconds = 0.0;   // includes the gather in the HitPoints organisation
  double index_seconds = 0.0;   // building the spatial index
  double gather_seconds = 0.0;  // Photons organisation: hit points gathering
};

class PhotonPass {
 public:
  PhotonPass(const Settings& settings, int threads);

  // Runs one pass. Returns false if cancelled; the statistics are then untouched.
  bool run(const Scene& scene, const LightSampler& lights, uint64_t pass, HitPoints& hp,
           std::atomic<bool>& cancel, const std::function<bool()>& poll, PhotonPassCounters& counters);

  // The Photons organisation in two steps, for hit points made band by band (stochastic hit
  // points): trace and index the pass's photons (`typical_r2`, a hit point's radius^2, sizes the
  // hashed grid's cells), then gather them into each band. False if cancelled.
  bool indexes_photons() const { return settings_.gather == GatherOrganisation::Photons; }
  bool trace_and_index(const Scene& scene, const LightSampler& lights, uint64_t pass, double typical_r2,
                       std::atomic<bool>& cancel, const std::function<bool()>& poll, PhotonPassCounters& counters);
  bool gather(const Scene& scene, HitPoints& hp, std::atomic<bool>& cancel, const std::function<bool()>& poll,
              PhotonPassCounters& counters);
  // Scenes with media (photon_tracer_media.h): the pass's volume photons, kept apart from the
  // surface photons in a grid of their own, gathered into each hit point in a medium (`points`:
  // their m and tau, the photons within the sphere of radius r weighted by the phase function and
  // the hit point's weight). False if cancelled.
  bool gather_volume(const Scene& scene, std::vector<VolumeHitPoint>& points, std::atomic<bool>& cancel,
                     const std::function<bool()>& poll, PhotonPassCounters& counters);
  // The same into beams through homogeneous media (hit_point.h's VolumeBeam; photon_pass_beams.cpp):
  // their m, tau and bias sum from the photons within r of each. False if cancelled.
  bool gather_beams(const Scene& scene, std::vector<VolumeBeam>& beams, std::atomic<bool>& cancel,
                    const std::function<bool()>& poll, PhotonPassCounters& counters);
  size_t volume_photons() const { return volume_positions_.size(); }

  // The photons (as traced and in cell order), the spatial index, and what the pass keeps per hit point.
  size_t photon_bytes() const;
  size_t index_bytes() const;
  size_t per_hit_point_bytes() const;
  // The hit points changed (stochastic PPM): rebuild the hit-point index before the next pass.
  void reset_index() { index_built_ = false; }

  // Photon guiding (Settings::photon_guiding, photon_guide.h): each pixel's weight for the gathers
  // to come (bottom row first; kept by the caller), and the end of a pass, which folds what its
  // gathers credited into the guide.
  void set_guide_weights(const std::vector<float>* pixel_weights) { guide_weights_ = pixel_weights; }
  // A band's credits count once it is folded into the image (a band cancelled after its gather is
  // gathered again; run() keeps its one band's at once).
  void keep_band_credit();
  void learn_guide();
  const PhotonGuide& guide() const { return guide_; }

 private:
  struct Photon {
    Vec3 position;
    Vec3f direction;
    Vec3f normal;  // of the surface, on the side the photon arrived on
    Vec3f flux;
    Bounces bounces;  // with bounce limits (in what would be padding)
  };
  // The rest of a photon, in cell order beside its position; read only for
  // the photons that pass the distance test.
  struct Arrival {
    Vec3f normal;
    Vec3f flux;
    Vec3f direction;
  };

  template <class Grid>
  bool run_hit_point_index(const Grid& grid, const Scene& scene, const LightSampler& lights, uint64_t pass,
                           HitPoints& hp, std::atomic<bool>& cancel, const std::function<bool()>& poll,
                           PhotonPassCounters& counters);
  // The three steps of a Photons-organisation pass.
  bool trace_into_chunks(const Scene& scene, const LightSampler& lights, uint64_t pass, size_t chunks,
                         std::atomic<bool>& cancel, const std::function<bool()>& poll);
  template <class Grid>
  size_t index_photons(Grid& grid, size_t chunks, double typical_r2);
  size_t index_volume_photons(size_t chunks);
  // One hit point's photons by class of lobe, the caustic ones last (light_components.h).
  struct PhotonParts {
    Vec3f flux[kPhotonParts];
  };
  // What one hit point gathers from a pass's indexed photons (luminance bias, error_estimate.h).
  struct Gathered {
    uint32_t m = 0;
    Color tau{0.0};
    double bias = 0.0;
  };
  // kTagged: photons carry tags to read (caustic flags with light components, guide origins).
  template <class Grid, bool kLimits, bool kTagged>
  void gather_diffuse(const Grid& grid, const HitPoints& hp, size_t i, Gathered& g, PhotonParts* parts,
                      double* credit) const;
  template <class Grid, bool kTagged>
  void gather_glossy(const Grid& grid, const Scene& scene, const HitPoints& hp, size_t i, Gathered& g,
                     PhotonParts* parts, double* credit) const;
  // Hit point i's guide credit per unit of luminance it gathers (0: none to give).
  double guide_weight(const HitPoints& hp, size_t i) const;
  template <class Grid>
  bool gather_at_hit_points(const Grid& grid, const Scene& scene, const HitPoints& hp, std::atomic<bool>& cancel,
                            const std::function<bool()>& poll);
  void build_hit_point_index(const HitPoints& hp, PhotonPassCounters& counters);
  double mean_r2(const HitPoints& hp) const;

  Settings settings_;
  int threads_;
  BounceLimits limits_;  // of the scene of the current pass
  QuantileGrid quantile_;
  HashGrid hash_;
  double indexed_mean_r2_ = 0.0;  // mean r^2 when the hit-point index was last built
  bool index_built_ = false;
  // Per-block accumulators (HitPoints organisation).
  std::vector<std::vector<uint32_t>> m_acc_;
  std::vector<std::vector<Vec3f>> tau_acc_;
  std::vector<std::vector<float>> bias_acc_;  // luminance (error_estimate.h)
  std::vector<uint64_t> deposits_;
  // Photons organisation: photons per chunk as traced; their positions
  // concatenated in chunk order (the traced order) for the grid, then all of
  // them stored in cell order as positions + arrivals.
  std::vector<std::vector<Photon>> chunk_photons_;
  std::vector<size_t> chunk_first_;     // traced index of each chunk's first photon
  std::vector<Vec3> traced_positions_;  // grid input, in traced order
  std::vector<uint32_t> old_of_new_;    // traced index of each photon in cell order
  std::vector<uint32_t> new_of_old_;    // and the inverse
  std::vector<Vec3> positions_;         // cell order
  std::vector<Arrival> arrivals_;       // cell order
  std::vector<Bounces> arrival_bounces_;  // cell order, with bounce limits only
  // With light components (Settings::component_passes): whether each photon is a caustic one, per
  // chunk as traced and in cell order.
  std::vector<std::vector<uint8_t>> chunk_caustic_;
  std::vector<uint8_t> arrival_caustic_;
  // Photon guiding: the guide, each photon's origin (per chunk as traced, then in cell order), the
  // pixels' weights, and the credits (per chunk of hit points, summed in chunk order: the same
  // whichever thread gathered which) of the last band gathered and of the pass's bands kept.
  PhotonGuide guide_;
  bool guide_ready_ = false;
  std::vector<std::vector<int32_t>> chunk_origin_;
  std::vector<int32_t> arrival_origin_;
  const std::vector<float>* guide_weights_ = nullptr;
  std::vector<std::vector<double>> chunk_credit_;
  std::vector<double> band_credit_, pass_credit_;
  // One pass's gather per hit point, added to the statistics once the pass completes.
  std::vector<uint32_t> gathered_m_;
  std::vector<Color> gathered_tau_;
  std::vector<float> gathered_bias_;  // luminance (error_estimate.h)
  std::vector<PhotonParts> gathered_parts_;  // with light components
  std::vector<Vec3> centers_;
  std::vector<double> radii_;
  // Volume photons (scenes with media): per chunk as traced, then in their grid's cell order.
  struct VolumePhoton {
    Vec3 position;
    Vec3f direction;  // of travel into the scattering point
    Vec3f flux;       // times sigma_s T / pdf (photon_tracer_media.h)
    bool beamed;      // a photon beam carried it here too
  };
  struct VolumeArrival {
    Vec3f direction;
    Vec3f flux;
    bool beamed;
  };
  bool media_ = false;  // the pass's scene has media
  std::vector<std::vector<VolumePhoton>> chunk_volume_;
  std::vector<std::vector<Bounces>> chunk_volume_bounces_;  // with bounce limits only, beside chunk_volume_
  QuantileGrid volume_grid_;
  std::vector<Vec3> volume_traced_, volume_positions_;
  std::vector<VolumeArrival> volume_arrivals_;
  std::vector<Bounces> volume_arrival_bounces_;  // with bounce limits only, beside volume_arrivals_
  std::vector<uint32_t> volume_old_of_new_;
  // With Settings::volume_beams: the photon beams per chunk as traced, then indexed.
  std::vector<std::vector<PhotonBeam>> chunk_beams_;
  PhotonBeamIndex photon_beams_;
  void index_photon_beams(uint64_t pass, size_t chunks);
  void gather_beam(const Scene& scene, VolumeBeam& beam) const;
};

}  // namespace ppm
