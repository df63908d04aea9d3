// Photon passes (see photon_pass.h).
#include "ppm/photon_pass.h"

#include "ppm/parallel.h"
#include "ppm/photon_tracer.h"

#include <chrono>
#include <cstring>

namespace ppm {
namespace {

constexpr uint64_t kPhotonStream = 2ull << 40;
constexpr size_t kPhotonChunk = 1024;
constexpr size_t kHitPointChunk = 4096;
// Rebuild the hit-point index once the mean radius^2 has halved: a stale index
// is still correct (radii only shrink) but visits more candidates.
constexpr double kReindexRatio = 0.5;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Does a photon at `pos` travelling along `dir` count for hit point i, and with what weight?
inline bool photon_weight(const Scene& scene, const HitPoints& hp, uint32_t i, const Vec3& pos,
                          const Vec3f& dir, Vec3f& weight) {
  const HitPoint& h = hp.points[i];
  const Vec3 d = pos - h.position;
  if (glm::dot(d, d) > h.r2) return false;
  if (!h.glossy) {
    if (glm::dot(h.normal, dir) >= 0.0f) return false;  // arrived on the back side
    weight = h.weight;
    return true;
  }
  const HitPointShading& sh = hp.shading[h.shading];
  const SurfacePoint sp{sh.geometric_normal, sh.shading_normal, sh.albedo};
  weight = Vec3f(sh.throughput * bsdf_eval(scene.material(sh.material), sp, sh.wo, -Vec3(dir)));
  return weight.x > 0.0f || weight.y > 0.0f || weight.z > 0.0f;
}

}  // namespace

PhotonPass::PhotonPass(const Settings& settings, int threads)
    : settings_(settings), threads_(threads), m_acc_(threads), tau_acc_(threads), deposits_(threads),
      photon_buffers_(threads) {}

double PhotonPass::mean_r2(const HitPoints& hp) const {
  double sum = 0.0;
  for (const HitPoint& h : hp.points) sum += h.r2;
  return hp.size() ? sum / hp.size() : 0.0;
}

void PhotonPass::build_hit_point_index(const HitPoints& hp, PhotonPassCounters& counters) {
  const auto t0 = std::chrono::steady_clock::now();
  centers_.resize(hp.size());
  radii_.resize(hp.size());
  for (size_t i = 0; i < hp.size(); ++i) {
    centers_[i] = hp.points[i].position;
    radii_[i] = std::sqrt(hp.points[i].r2);
  }
  const double current_mean_r2 = mean_r2(hp);
  if (settings_.grid == GridKind::Quantile)
    quantile_.build(centers_, radii_);
  else
    hash_.build(centers_, radii_, std::fmax(2.0 * std::sqrt(current_mean_r2), 1e-300));
  indexed_mean_r2_ = current_mean_r2;
  index_built_ = true;
  counters.index_seconds += seconds_since(t0);
}

bool PhotonPass::run(const Scene& scene, const LightSampler& lights, uint64_t pass, HitPoints& hp,
                     std::atomic<bool>& cancel, const std::function<bool()>& poll, PhotonPassCounters& counters) {
  if (settings_.gather == GatherOrganisation::HitPoints) {
    if (!index_built_ || mean_r2(hp) < kReindexRatio * indexed_mean_r2_) build_hit_point_index(hp, counters);
    return settings_.grid == GridKind::Quantile
               ? run_hit_point_index(quantile_, scene, lights, pass, hp, cancel, poll, counters)
               : run_hit_point_index(hash_, scene, lights, pass, hp, cancel, poll, counters);
  }
  return settings_.grid == GridKind::Quantile
             ? run_photon_index(quantile_, scene, lights, pass, hp, cancel, poll, counters)
             : run_photon_index(hash_, scene, lights, pass, hp, cancel, poll, counters);
}

template <class Grid>
bool PhotonPass::run_hit_point_index(const Grid& grid, const Scene& scene, const LightSampler& lights,
                                     uint64_t pass, HitPoints& hp, std::atomic<bool>& cancel,
                                     const std::function<bool()>& poll, PhotonPassCounters& counters) {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = hp.size();
  for (int t = 0; t < threads_; ++t) {
    m_acc_[t].assign(n, 0u);
    tau_acc_[t].assign(n, Vec3f(0.0f));
    deposits_[t] = 0;
  }
  const uint64_t photons = settings_.photons_per_pass;
  const size_t chunks = (photons + kPhotonChunk - 1) / kPhotonChunk;
  auto work = [&](int thread, size_t chunk) {
    uint32_t* m = m_acc_[thread].data();
    Vec3f* tau = tau_acc_[thread].data();
    uint64_t deposits = 0;
    for (uint64_t i = chunk * kPhotonChunk; i < std::min<uint64_t>(photons, (chunk + 1) * kPhotonChunk); ++i) {
      Rng rng(settings_.seed, kPhotonStream + pass, i);
      deposits += trace_photon(scene, lights, settings_, rng, [&](const Vec3& pos, const Vec3& dir, const Color& flux) {
        const Vec3f d(dir), f(flux);
        grid.for_each_candidate_at(pos, [&](uint32_t h) {
          Vec3f w;
          if (!photon_weight(scene, hp, h, pos, d, w)) return;
          ++m[h];
          tau[h] += w * f;
        });
      });
    }
    deposits_[thread] += deposits;
  };
  const int threads = std::max(1, std::min<int>(threads_, static_cast<int>(chunks)));
  if (!parallel_chunks(threads, chunks, work, cancel, poll, settings_.progress_interval)) return false;
  for (int t = 0; t < threads; ++t) {  // merge in thread order: deterministic sums
    const uint32_t* m = m_acc_[t].data();
    const Vec3f* tau = tau_acc_[t].data();
    for (size_t i = 0; i < n; ++i) {
      if (m[i] == 0) continue;
      hp.stats[i].m += m[i];
      hp.stats[i].tau_m += Color(tau[i]);
    }
    counters.deposited += deposits_[t];
  }
  counters.emitted += photons;
  counters.trace_seconds += seconds_since(t0);
  return true;
}

template <class Grid>
bool PhotonPass::run_photon_index(Grid& grid, const Scene& scene, const LightSampler& lights, uint64_t pass,
                                  HitPoints& hp, std::atomic<bool>& cancel, const std::function<bool()>& poll,
                                  PhotonPassCounters& counters) {
  auto t0 = std::chrono::steady_clock::now();
  const uint64_t photons = settings_.photons_per_pass;
  const size_t chunks = (photons + kPhotonChunk - 1) / kPhotonChunk;
  // Buffers per chunk would keep photon order independent of the thread count;
  // per thread is enough for "same seed + same threads = same image".
  for (auto& b : photon_buffers_) b.clear();
  auto trace = [&](int thread, size_t chunk) {
    auto& buffer = photon_buffers_[thread];
    for (uint64_t i = chunk * kPhotonChunk; i < std::min<uint64_t>(photons, (chunk + 1) * kPhotonChunk); ++i) {
      Rng rng(settings_.seed, kPhotonStream + pass, i);
      trace_photon(scene, lights, settings_, rng, [&](const Vec3& pos, const Vec3& dir, const Color& flux) {
        buffer.push_back(Photon{pos, Vec3f(dir), Vec3f(flux)});
      });
    }
  };
  const int trace_threads = std::max(1, std::min<int>(threads_, static_cast<int>(chunks)));
  if (!parallel_chunks(trace_threads, chunks, trace, cancel, poll, settings_.progress_interval)) return false;
  photons_.clear();
  for (auto& b : photon_buffers_) photons_.insert(photons_.end(), b.begin(), b.end());
  counters.trace_seconds += seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  photon_positions_.resize(photons_.size());
  for (size_t i = 0; i < photons_.size(); ++i) photon_positions_[i] = photons_[i].position;
  static const std::vector<double> kNoRadii;
  if constexpr (std::is_same_v<Grid, HashGrid>)
    grid.build(photon_positions_, kNoRadii, std::fmax(2.0 * std::sqrt(mean_r2(hp)), 1e-300));
  else
    grid.build(photon_positions_, kNoRadii);
  // Store the photons in the grid's cell order: a hit point's candidates then
  // sit next to each other in memory instead of all over the pass's array.
  const std::vector<uint32_t> old_of_new = grid.relabel_in_cell_order();
  sorted_photons_.resize(photons_.size());
  for (size_t i = 0; i < old_of_new.size(); ++i) sorted_photons_[i] = photons_[old_of_new[i]];
  photons_.swap(sorted_photons_);
  counters.index_seconds += seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const size_t n = hp.size(), hchunks = (n + kHitPointChunk - 1) / kHitPointChunk;
  std::vector<uint32_t> m(n, 0);
  std::vector<Color> tau(n, Color(0.0));
  auto gather = [&](int, size_t chunk) {
    for (size_t i = chunk * kHitPointChunk; i < std::min(n, (chunk + 1) * kHitPointChunk); ++i) {
      const HitPoint& h = hp.points[i];
      const Vec3 r(std::sqrt(h.r2));
      grid.for_each_candidate_in_box(h.position - r, h.position + r, [&](uint32_t p) {
        const Photon& ph = photons_[p];
        Vec3f w;
        if (!photon_weight(scene, hp, static_cast<uint32_t>(i), ph.position, ph.direction, w)) return;
        ++m[i];
        tau[i] += Color(w * ph.flux);
      });
    }
  };
  const int gather_threads = std::max(1, std::min<int>(threads_, static_cast<int>(hchunks)));
  if (!parallel_chunks(gather_threads, hchunks, gather, cancel, poll, settings_.progress_interval)) return false;
  for (size_t i = 0; i < n; ++i) {
    hp.stats[i].m += m[i];
    hp.stats[i].tau_m += tau[i];
  }
  counters.deposited += photons_.size();
  counters.emitted += photons;
  counters.gather_seconds += seconds_since(t0);
  return true;
}

size_t PhotonPass::memory_bytes() const {
  size_t bytes = quantile_.memory_bytes() + hash_.memory_bytes();
  for (const auto& v : m_acc_) bytes += v.capacity() * sizeof(uint32_t);
  for (const auto& v : tau_acc_) bytes += v.capacity() * sizeof(Vec3f);
  for (const auto& v : photon_buffers_) bytes += v.capacity() * sizeof(Photon);
  bytes += (photons_.capacity() + sorted_photons_.capacity()) * sizeof(Photon) +
           photon_positions_.capacity() * sizeof(Vec3);
  bytes += centers_.capacity() * sizeof(Vec3) + radii_.capacity() * sizeof(double);
  return bytes;
}

}  // namespace ppm
