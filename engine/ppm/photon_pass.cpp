// Photon passes (see photon_pass.h).
#include "ppm/photon_pass.h"

#include "ppm/error_estimate.h"
#include "base/parallel.h"
#include "ppm/photon_tracer.h"
#include "ppm/photon_tracer_media.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <type_traits>

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

// Which photons within r of a hit point count for it: those that arrived on
// its front side (the side its normal is turned to), unless the two lie on
// either side of a solid, which the distance test alone cannot see: a light
// inside a closed box leaked out along the box's outside edges, because a hit
// point on the outside of one face gathered the photons on the inside of the
// adjacent face. Such a photon lies behind the hit point's tangent plane, the
// hit point lies in front of the photon's (its normal turned to the side it
// arrived on), and the normals are more than 60 degrees apart. Photons on the
// outside of the adjacent face (the hit point is behind their plane), on a
// curved surface (normals about r / radius of curvature apart) and past an
// inside corner (in front of the hit point's plane) all still count; the last
// two make up for the part of the gather disc beyond an edge, where no photon
// of the hit point's own surface can land (counting none there darkened the
// edges of the diffuse Cornell box by 1% at 80x60 pixels).
constexpr float kSameSurfaceCos = 0.5f;

// d = photon position - hit point position.
inline bool across_a_solid(const Vec3& d, const Vec3& normal, const Vec3f& normal_f, const Vec3f& photon_normal) {
  return glm::dot(d, normal) < 0.0 && glm::dot(d, Vec3(photon_normal)) < 0.0 &&
         glm::dot(normal_f, photon_normal) <= kSameSurfaceCos;
}

// Diffuse hit points, once |d| <= r is known.
inline bool counts_for_diffuse(const Vec3& d, const Vec3& normal, const Vec3f& normal_f, const Vec3f& direction,
                               const Vec3f& photon_normal) {
  if (glm::dot(normal_f, direction) >= 0.0f) return false;  // arrived on the back side
  return !across_a_solid(d, normal, normal_f, photon_normal);
}

// Whether a photon at `pos`, arrived on the side `photon_normal` faces, counts for glossy hit point i:
// within its radius and on a side its material scatters from (glass and translucent lobes
// transmit: photons that arrived on the other side count through the BSDF).
inline bool reaches_glossy(const Scene& scene, const HitPoints& hp, uint32_t i, const Vec3& pos,
                           const Vec3f& photon_normal) {
  const HitPoint& h = hp.points[i];
  const Vec3 d = pos - h.position;
  if (glm::dot(d, d) > h.r2) return false;
  return transmits(scene.material(hp.shading[h.shading].material)) ||
         !across_a_solid(d, Vec3(h.normal), h.normal, photon_normal);
}

// Does a photon at `pos` travelling along `dir` count for hit point i, and with what weight?
inline bool photon_weight(const Scene& scene, const HitPoints& hp, uint32_t i, const Vec3& pos, const Vec3f& dir,
                          const Vec3f& photon_normal, Vec3f& weight) {
  const HitPoint& h = hp.points[i];
  if (!h.glossy) {
    const Vec3 d = pos - h.position;
    if (glm::dot(d, d) > h.r2 || !counts_for_diffuse(d, Vec3(h.normal), h.normal, dir, photon_normal)) return false;
    weight = h.weight;
    return true;
  }
  if (!reaches_glossy(scene, hp, i, pos, photon_normal)) return false;
  const HitPointShading& sh = hp.shading[h.shading];
  const SurfacePoint sp = scene.surface_point(surface_record(h, sh));
  weight = sh.throughput * Vec3f(bsdf_eval(scene.material(sh.material), sp, Vec3(sh.wo), -Vec3(dir)));
  return weight.x > 0.0f || weight.y > 0.0f || weight.z > 0.0f;
}

// photon_weight split by class of lobe, for a glossy hit point with light components.
inline bool photon_weight_classes(const Scene& scene, const HitPoints& hp, uint32_t i, const Vec3& pos,
                                  const Vec3f& dir, const Vec3f& photon_normal, ClassColors& weight) {
  if (!reaches_glossy(scene, hp, i, pos, photon_normal)) return false;
  const HitPoint& h = hp.points[i];
  const HitPointShading& sh = hp.shading[h.shading];
  const SurfacePoint sp = scene.surface_point(surface_record(h, sh));
  weight = bsdf_eval_classes(scene.material(sh.material), sp, Vec3(sh.wo), -Vec3(dir));
  for (Color& c : weight.c) c *= Color(sh.throughput);
  return max_component(weight.total()) > 0.0;
}

// Bounce limits: does a photon whose path scattered `used` fit in what hit point i's eye chain left?
inline bool within_budget(const BounceLimits& limits, const HitPoints& hp, uint32_t i, Bounces used,
                          const Vec3f& photon_normal) {
  const HitPoint& h = hp.points[i];
  if (h.glossy && glm::dot(h.normal, photon_normal) < 0.0f) used = through_glass(used);
  return within(used, limits.budget(hp.chain[i]));
}

// The part of a gather ball (centre c, radius r) on the hit point's side of the nearest surface:
// no photon lies beyond a surface bounding the medium, so the estimate divides by its share of the
// ball, and the error estimate's curvature weight is centred on its E[d^2] / r^2 (error_estimate.h).
// Rays along the six axes up to 4r find the surface; a plane at distance d (unit normal n) meets
// axis k at d / |n_k|, so 1/d^2 = sum over the axes of 1/t_k^2 (each axis its nearer hit; an axis
// with |n_k| below d / 4r, missed, leaves at most 1/16 of the sum out). Beyond the plane lies the
// cap of height r - d: volume pi (r - d)^2 (2r + d) / 3, int |x|^2 = pi/2 (r^4 (r - d) - (r^5 - d^5) / 5).
// Where the surface only bounds the medium (a boundary, or a surface carrying a medium) and another
// that scatters lies beyond (a smoke ball in a fog room), photons lie there too, as many per volume
// as its sigma_s against this one's (the fluence goes on across): the cap counts at that ratio.
struct BallInside {
  double share = 1.0;
  double mean_d2 = 0.6;
  // The plane found (a unit normal towards it and its distance; none: distance inf) and sigma_s's
  // ratio beyond it, for the share of a medium that varies (ball_share_varying).
  Vec3 normal{0.0};
  double distance = kInf, beyond = 0.0, cap = 0.0;  // cap: the ball's share beyond the plane
};

// sigma_s beyond the surface at `hit` over sigma_s here (luminance), for a ray leaving a point in
// `media`: 0 where the surface is opaque or nothing scatters beyond.
double scattering_beyond(const Scene& scene, const Hit& hit, const Vec3& direction, const MediumStack& media,
                         double here) {
  const Material& m = scene.material(hit.material);
  if (m.surface && (m.medium < 0 || !transmits(m))) return 0.0;  // light does not pass it
  MediumStack beyond = media;
  scene.cross(hit, direction, beyond);
  const Medium* b = scene.medium_of(beyond);
  return b != nullptr && here > 0.0 ? luminance(scene.sigma_s_at(*b, hit.position, direction)) / here : 0.0;
}

BallInside ball_inside(const Scene& scene, const Vec3& c, double r, const MediumStack& media, double sigma_s) {
  double inverse_d2 = 0.0, nearest = kInf, beyond = 0.0;
  Vec3 toward(0.0);  // 1/t_k along each axis, signed: the plane's normal times 1/d
  for (int k = 0; k < 3; ++k) {
    double t = kInf, sign_of_t = 0.0;
    for (double sign : {1.0, -1.0}) {
      Ray ray{c, Vec3(0.0)};
      ray.direction[k] = sign;
      Hit hit;
      if (!scene.intersect(ray, hit, 4.0 * r)) continue;
      if (hit.t < t) t = hit.t, sign_of_t = sign;
      if (hit.t < nearest) nearest = hit.t, beyond = scattering_beyond(scene, hit, ray.direction, media, sigma_s);
    }
    if (t < kInf) inverse_d2 += 1.0 / (t * t), toward[k] = sign_of_t / t;
  }
  if (inverse_d2 == 0.0) return {};
  const double d = std::min(r, 1.0 / std::sqrt(inverse_d2)), r2 = r * r, r5 = r2 * r2 * r;
  const double ball = 4.0 * kPi * r2 * r / 3.0, cap = kPi * (r - d) * (r - d) * (2.0 * r + d) / 3.0;
  const double moment = 0.8 * kPi * r5 - kPi / 2.0 * (r2 * r2 * (r - d) - (r5 - std::pow(d, 5)) / 5.0);
  // As dense beyond or denser: the weight's centre as if uncut (the error estimate's only).
  const double mean_d2 = beyond >= 1.0 ? BallInside{}.mean_d2 : moment / ((ball - cap) * r2);
  return {1.0 - (1.0 - beyond) * cap / ball, mean_d2, toward / std::sqrt(inverse_d2), d, beyond, cap / ball};
}

// Fixed points spread evenly through the unit ball (radii by equal volumes, directions on a
// spherical Fibonacci spiral), where a varying medium's sigma_s is looked at over a gather ball.
constexpr int kShareSamples = 16;
const std::array<Vec3, kShareSamples>& ball_points() {
  static const std::array<Vec3, kShareSamples> points = [] {
    std::array<Vec3, kShareSamples> p{};
    for (int i = 0; i < kShareSamples; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / kShareSamples, phi = i * kPi * (3.0 - std::sqrt(5.0));
      const double radius = std::cbrt((((i * 7) % kShareSamples) + 0.5) / kShareSamples);
      const double ring = std::sqrt(1.0 - z * z);
      p[i] = radius * Vec3(ring * std::cos(phi), ring * std::sin(phi), z);
    }
    return p;
  }();
  return points;
}

// In a medium that varies, photons lie in proportion to sigma_s where they are, so a gather ball
// holds the ball's mean of sigma_s times the fluence, not the centre's: at a cloud's thin edge next
// to a dense part, too many (a smoke's wisps read bright), at a dense point among thin ones too few.
// The share divides that out: the mean over the ball of sigma_s(y) / sigma_s(centre), on this side of
// the nearest surface the mean at the centre and those of kShareSamples points that lie there, beyond
// it its `beyond` ratio (ball_inside's plane and cap, exact for a field that is constant).
double ball_share_varying(const Scene& scene, const Medium& medium, const Vec3& c, double r, const Vec3& direction,
                          double here, const BallInside& plane) {
  if (!(here > 0.0)) return plane.share;
  double sum = 1.0;  // the centre's
  int inside = 1;
  for (const Vec3& u : ball_points()) {
    if (glm::dot(u, plane.normal) * r > plane.distance) continue;
    sum += luminance(scene.sigma_s_at(medium, c + r * u, direction)) / here;
    ++inside;
  }
  return (1.0 - plane.cap) * sum / inside + plane.cap * plane.beyond;
}

}  // namespace

PhotonPass::PhotonPass(const Settings& settings, int threads)
    : settings_(settings), threads_(threads), m_acc_(threads), tau_acc_(threads), bias_acc_(threads),
      deposits_(threads) {}

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
  limits_ = BounceLimits::of(settings_, scene);
  if (settings_.gather == GatherOrganisation::HitPoints) {
    if ((!index_built_ || mean_r2(hp) < kReindexRatio * indexed_mean_r2_) &&
        !run_polled([&] { build_hit_point_index(hp, counters); }, cancel, poll, settings_.progress_interval))
      return false;
    return settings_.grid == GridKind::Quantile
               ? run_hit_point_index(quantile_, scene, lights, pass, hp, cancel, poll, counters)
               : run_hit_point_index(hash_, scene, lights, pass, hp, cancel, poll, counters);
  }
  if (!trace_and_index(scene, lights, pass, mean_r2(hp), cancel, poll, counters) ||
      !gather(scene, hp, cancel, poll, counters))
    return false;
  keep_band_credit();
  return true;
}

template <class Grid>
bool PhotonPass::run_hit_point_index(const Grid& grid, const Scene& scene, const LightSampler& lights,
                                     uint64_t pass, HitPoints& hp, std::atomic<bool>& cancel,
                                     const std::function<bool()>& poll, PhotonPassCounters& counters) {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = hp.size();
  const uint64_t photons = settings_.photons_per_pass;
  // One block of photons per thread, each with its own accumulator: a block's
  // sums do not depend on which thread ran it.
  const int blocks = std::max(1, std::min<int>(threads_, static_cast<int>((photons + kPhotonChunk - 1) / kPhotonChunk)));
  auto work = [&](int, size_t block) {
    m_acc_[block].assign(n, 0u);
    tau_acc_[block].assign(n, Vec3f(0.0f));
    bias_acc_[block].assign(n, 0.0f);
    uint32_t* m = m_acc_[block].data();
    Vec3f* tau = tau_acc_[block].data();
    float* bias = bias_acc_[block].data();
    uint64_t deposits = 0;
    const uint64_t first = photons * block / blocks, last = photons * (block + 1) / blocks;
    for (uint64_t begin = first; begin < last; begin += kPhotonChunk) {
      if (cancel.load(std::memory_order_relaxed)) return;
      deposits += trace_photons(
          scene, lights, settings_, limits_, begin, std::min(last, begin + kPhotonChunk),
          [&](uint64_t i) { return Rng(settings_.seed, kPhotonStream + pass, i); },
          [&](const Vec3& pos, const Vec3& dir, const Vec3& normal, const Color& flux, const Bounces& used,
              PhotonTag tag) {
            const Vec3f d(dir), nf(normal), f(flux);
            grid.for_each_candidate_at(pos, [&](uint32_t h) {
              Vec3f w;
              if (!photon_weight(scene, hp, h, pos, d, nf, w)) return;
              if (limits_.active && !within_budget(limits_, hp, h, used, nf)) return;
              ++m[h];
              const Vec3f wf = w * f;
              tau[h] += wf;
              const HitPoint& point = hp.points[h];
              const Vec3 d = pos - point.position;
              bias[h] += static_cast<float>(luminance(Color(wf)) * bias_weight(glm::dot(d, d), point.r2));
            });
          });
    }
    deposits_[block] = deposits;
  };
  if (!parallel_chunks(blocks, blocks, work, cancel, poll, settings_.progress_interval)) return false;
  parallel_for(threads_, n, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) hp.stats[i].pass_flux = hp.stats[i].pass_bias = 0.0f;
    for (int b = 0; b < blocks; ++b) {  // block order: deterministic sums
      const uint32_t* m = m_acc_[b].data();
      const Vec3f* tau = tau_acc_[b].data();
      const float* bias = bias_acc_[b].data();
      for (size_t i = begin; i < end; ++i) {
        if (m[i] == 0) continue;
        HitPointStats& s = hp.stats[i];
        s.m += m[i];
        s.tau_m += Color(tau[i]);
        s.pass_flux += static_cast<float>(luminance(Color(tau[i])));
        s.pass_bias += bias[i];
      }
    }
  });
  for (int b = 0; b < blocks; ++b) counters.deposited += deposits_[b];
  counters.emitted += photons;
  counters.trace_seconds += seconds_since(t0);
  return true;
}

// The traced photons of a Photons-organisation pass into the grid, and stored in its cell order;
// returns how many there are.
template <class Grid>
size_t PhotonPass::index_photons(Grid& grid, size_t chunks, double typical_r2) {
  // The grid's input: the positions, concatenated in chunk order (each chunk
  // copied by whichever thread takes it). The rest stays in the chunk buffers.
  chunk_first_.resize(chunks + 1);
  chunk_first_[0] = 0;
  for (size_t c = 0; c < chunks; ++c) chunk_first_[c + 1] = chunk_first_[c] + chunk_photons_[c].size();
  const size_t count = chunk_first_[chunks];
  traced_positions_.resize(count);
  parallel_each(threads_, chunks, [&](size_t c) {
    const std::vector<Photon>& buffer = chunk_photons_[c];
    Vec3* positions = traced_positions_.data() + chunk_first_[c];
    for (size_t k = 0; k < buffer.size(); ++k) positions[k] = buffer[k].position;
  });
  static const std::vector<double> kNoRadii;
  if constexpr (std::is_same_v<Grid, HashGrid>)
    grid.build(traced_positions_, kNoRadii, std::fmax(2.0 * std::sqrt(typical_r2), 1e-300));
  else
    grid.build(traced_positions_, kNoRadii, threads_);
  // Store the photons in the grid's cell order, straight from the chunk
  // buffers: a hit point's candidates then sit next to each other in memory
  // instead of all over the pass's array.
  grid.relabel_in_cell_order(old_of_new_);
  new_of_old_.resize(count);
  parallel_for(threads_, count, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) new_of_old_[old_of_new_[i]] = static_cast<uint32_t>(i);
  });
  positions_.resize(count);
  arrivals_.resize(count);
  arrival_bounces_.resize(limits_.active ? count : 0);
  const bool caustics = settings_.component_passes, guided = settings_.photon_guiding;
  arrival_caustic_.resize(caustics ? count : 0);
  arrival_origin_.resize(guided ? count : 0);
  parallel_each(threads_, chunks, [&](size_t c) {
    const std::vector<Photon>& buffer = chunk_photons_[c];
    const uint32_t* new_index = new_of_old_.data() + chunk_first_[c];
    for (size_t k = 0; k < buffer.size(); ++k) {
      const Photon& p = buffer[k];
      positions_[new_index[k]] = p.position;
      arrivals_[new_index[k]] = Arrival{p.normal, p.flux, p.direction};
      if (limits_.active) arrival_bounces_[new_index[k]] = p.bounces;
      if (caustics) arrival_caustic_[new_index[k]] = chunk_caustic_[c][k];
      if (guided) arrival_origin_[new_index[k]] = chunk_origin_[c][k];
    }
  });
  return count;
}

bool PhotonPass::trace_and_index(const Scene& scene, const LightSampler& lights, uint64_t pass, double typical_r2,
                                 std::atomic<bool>& cancel, const std::function<bool()>& poll,
                                 PhotonPassCounters& counters) {
  limits_ = BounceLimits::of(settings_, scene);
  if (settings_.photon_guiding && !guide_ready_) {
    guide_.reset(scene.lights());
    guide_ready_ = true;
  }
  const size_t chunks = (settings_.photons_per_pass + kPhotonChunk - 1) / kPhotonChunk;
  auto t0 = std::chrono::steady_clock::now();
  if (!trace_into_chunks(scene, lights, pass, chunks, cancel, poll)) return false;
  counters.trace_seconds += seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  size_t count = 0;
  auto index = [&] {
    count = settings_.grid == GridKind::Quantile ? index_photons(quantile_, chunks, typical_r2)
                                                 : index_photons(hash_, chunks, typical_r2);
  };
  if (!run_polled(index, cancel, poll, settings_.progress_interval)) return false;
  if (media_ && !run_polled([&] { count += index_volume_photons(chunks); }, cancel, poll, settings_.progress_interval))
    return false;
  if (media_ && settings_.volume_beams &&
      !run_polled([&] { index_photon_beams(pass, chunks); }, cancel, poll, settings_.progress_interval))
    return false;
  counters.index_seconds += seconds_since(t0);
  counters.deposited += count;
  counters.emitted += settings_.photons_per_pass;
  return true;
}

bool PhotonPass::gather(const Scene& scene, HitPoints& hp, std::atomic<bool>& cancel,
                        const std::function<bool()>& poll, PhotonPassCounters& counters) {
  const auto t0 = std::chrono::steady_clock::now();
  const bool gathered = settings_.grid == GridKind::Quantile ? gather_at_hit_points(quantile_, scene, hp, cancel, poll)
                                                             : gather_at_hit_points(hash_, scene, hp, cancel, poll);
  if (!gathered) return false;
  parallel_for(threads_, hp.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      HitPointStats& s = hp.stats[i];
      s.m += gathered_m_[i];
      s.tau_m += gathered_tau_[i];
      s.pass_flux = static_cast<float>(luminance(gathered_tau_[i]));
      s.pass_bias = gathered_bias_[i];
      if (!gathered_parts_.empty())
        for (int k = 0; k < kPhotonParts; ++k) hp.components[i].tau_m[k] += gathered_parts_[i].flux[k];
    }
  });
  counters.gather_seconds += seconds_since(t0);
  return true;
}

// The pass's photons, traced in parallel into one buffer per chunk (kept across
// passes): merged in chunk order, the photon list is the same whichever thread
// traced which chunk.
bool PhotonPass::trace_into_chunks(const Scene& scene, const LightSampler& lights, uint64_t pass, size_t chunks,
                                   std::atomic<bool>& cancel, const std::function<bool()>& poll) {
  const uint64_t photons = settings_.photons_per_pass;
  if (chunk_photons_.size() < chunks) chunk_photons_.resize(chunks);
  const bool caustics = settings_.component_passes, guided = settings_.photon_guiding;
  if (caustics && chunk_caustic_.size() < chunks) chunk_caustic_.resize(chunks);
  if (guided && chunk_origin_.size() < chunks) chunk_origin_.resize(chunks);
  media_ = scene.has_media();
  if (media_ && chunk_volume_.size() < chunks) chunk_volume_.resize(chunks);
  if (media_ && limits_.active && chunk_volume_bounces_.size() < chunks) chunk_volume_bounces_.resize(chunks);
  const bool beams = media_ && settings_.volume_beams;
  if (beams && chunk_beams_.size() < chunks) chunk_beams_.resize(chunks);
  auto trace = [&](int, size_t chunk) {
    auto& buffer = chunk_photons_[chunk];
    buffer.clear();
    if (caustics) chunk_caustic_[chunk].clear();
    if (guided) chunk_origin_[chunk].clear();
    auto rng_of = [&](uint64_t i) { return Rng(settings_.seed, kPhotonStream + pass, i); };
    auto deposit = [&](const Vec3& pos, const Vec3& dir, const Vec3& normal, const Color& flux, const Bounces& used,
                       PhotonTag tag) {
      buffer.push_back(Photon{pos, Vec3f(dir), Vec3f(normal), Vec3f(flux), used});
      if (caustics) chunk_caustic_[chunk].push_back(tag.caustic);
      if (guided) chunk_origin_[chunk].push_back(tag.origin);
    };
    const uint64_t first = chunk * kPhotonChunk, last = std::min<uint64_t>(photons, (chunk + 1) * kPhotonChunk);
    if (!media_) {
      trace_photons(scene, lights, settings_, limits_, first, last, rng_of, deposit, guided ? &guide_ : nullptr);
      return;
    }
    auto& volume = chunk_volume_[chunk];
    volume.clear();
    std::vector<Bounces>* volume_bounces = limits_.active ? &chunk_volume_bounces_[chunk] : nullptr;
    if (volume_bounces) volume_bounces->clear();
    if (beams) chunk_beams_[chunk].clear();
    trace_photons_in_media(
        scene, lights, settings_, limits_, first, last, rng_of, deposit,
        [&](const Vec3& pos, const Vec3& dir, const Color& flux, const Bounces& used, bool beamed) {
          volume.push_back(VolumePhoton{pos, Vec3f(dir), Vec3f(flux), beamed});
          if (volume_bounces) volume_bounces->push_back(used);
        },
        [&](const PhotonBeam& b) { chunk_beams_[chunk].push_back(b); }, guided ? &guide_ : nullptr);
  };
  return parallel_chunks(threads_, chunks, trace, cancel, poll, settings_.progress_interval);
}

// Diffuse hit point i: the weight is the same for every photon, so it sums the flux and weighs
// once. Compiled for each case, so that the common loop has no test for limits or components.
template <class Grid, bool kLimits, bool kTagged>
void PhotonPass::gather_diffuse(const Grid& grid, const HitPoints& hp, size_t i, Gathered& g, PhotonParts* parts,
                                double* credit) const {
  const HitPoint& h = hp.points[i];
  const Vec3 center = h.position;
  const double r2 = h.r2, r = std::sqrt(r2);
  const Vec3f normal_f = h.normal;
  const Vec3 normal(normal_f);
  const Bounces budget = kLimits ? limits_.budget(hp.chain[i]) : Bounces{};
  const Vec3* position = positions_.data();
  const Arrival* arrival = arrivals_.data();
  Color flux(0.0), flux_d2(0.0), caustic_flux(0.0);
  const double credit_weight = kTagged && credit ? guide_weight(hp, i) : 0.0;
  grid.for_each_run_in_box(center - r, center + r, [&](uint32_t begin, uint32_t end) {
    for (uint32_t p = begin; p < end; ++p) {
      // Most candidates fail the distance test, which reads positions only.
      const Vec3 d = position[p] - center;
      const double d2 = glm::dot(d, d);
      if (d2 > r2) continue;
      const Arrival& a = arrival[p];
      if (!counts_for_diffuse(d, normal, normal_f, a.direction, a.normal)) continue;
      if constexpr (kLimits) {
        if (!within(arrival_bounces_[p], budget)) continue;
      }
      ++g.m;
      flux += Color(a.flux);
      flux_d2 += Color(a.flux) * d2;
      if constexpr (kTagged) {
        if (parts && arrival_caustic_[p]) caustic_flux += Color(a.flux);
        if (credit_weight > 0.0 && arrival_origin_[p] >= 0)
          credit[arrival_origin_[p]] += credit_weight * luminance(Color(a.flux) * Color(h.weight));
      }
    }
  });
  g.tau = flux * Color(h.weight);
  g.bias = luminance(bias_sum(flux, flux_d2, r2) * Color(h.weight));
  if (parts) {  // a diffuse hit point scatters by its diffuse lobe alone
    parts->flux[kDiffuseClass] = Vec3f(g.tau);
    parts->flux[kLightClasses] = Vec3f(caustic_flux * Color(h.weight));
  }
}

// Glossy hit point i: the BSDF evaluated per photon (by class of lobe with components).
template <class Grid, bool kTagged>
void PhotonPass::gather_glossy(const Grid& grid, const Scene& scene, const HitPoints& hp, size_t i, Gathered& g,
                               PhotonParts* parts, double* credit) const {
  const HitPoint& h = hp.points[i];
  const Vec3 center = h.position;
  const double r2 = h.r2, r = std::sqrt(r2);
  const uint32_t index = static_cast<uint32_t>(i);
  const double credit_weight = kTagged && credit ? guide_weight(hp, i) : 0.0;
  grid.for_each_run_in_box(center - r, center + r, [&](uint32_t begin, uint32_t end) {
    for (uint32_t p = begin; p < end; ++p) {
      const Arrival& a = arrivals_[p];
      ClassColors split;
      Vec3f w;
      if (kTagged && parts) {
        if (!photon_weight_classes(scene, hp, index, positions_[p], a.direction, a.normal, split)) continue;
        w = Vec3f(split.total());
      } else {
        if (!photon_weight(scene, hp, index, positions_[p], a.direction, a.normal, w)) continue;
      }
      if (limits_.active && !within_budget(limits_, hp, index, arrival_bounces_[p], a.normal)) continue;
      ++g.m;
      const Color wf(w * a.flux);
      g.tau += wf;
      const Vec3 d = positions_[p] - center;
      g.bias += luminance(wf) * bias_weight(glm::dot(d, d), r2);
      if constexpr (kTagged) {
        if (parts) {
          for (int c = 0; c < kLightClasses; ++c) parts->flux[c] += Vec3f(split.c[c] * Color(a.flux));
          if (arrival_caustic_[p]) parts->flux[kLightClasses] += Vec3f(wf);
        }
        if (credit_weight > 0.0 && arrival_origin_[p] >= 0) credit[arrival_origin_[p]] += credit_weight * luminance(wf);
      }
    }
  });
}

// Every hit point sums the indexed photons within its radius into gathered_m_ and gathered_tau_
// (by class into gathered_parts_ with light components; with guiding, the band's credits into
// band_credit_).
template <class Grid>
bool PhotonPass::gather_at_hit_points(const Grid& grid, const Scene& scene, const HitPoints& hp,
                                      std::atomic<bool>& cancel, const std::function<bool()>& poll) {
  const size_t n = hp.size(), hchunks = (n + kHitPointChunk - 1) / kHitPointChunk;
  gathered_m_.resize(n);
  gathered_tau_.resize(n);
  gathered_bias_.resize(n);
  const bool split = !hp.components.empty();
  gathered_parts_.resize(split ? n : 0);
  const bool crediting = !arrival_origin_.empty() && guide_weights_ != nullptr;
  if (crediting && chunk_credit_.size() < hchunks) chunk_credit_.resize(hchunks);
  auto gather = [&](auto tagged) {
    constexpr bool kTagged = decltype(tagged)::value;
    return [&](int, size_t chunk) {
      double* credit = nullptr;
      if (crediting) {
        chunk_credit_[chunk].assign(static_cast<size_t>(guide_.slots()) * PhotonGuide::kBins, 0.0);
        credit = chunk_credit_[chunk].data();
      }
      for (size_t i = chunk * kHitPointChunk; i < std::min(n, (chunk + 1) * kHitPointChunk); ++i) {
        Gathered g;
        PhotonParts* parts = split ? &gathered_parts_[i] : nullptr;
        if (parts) *parts = PhotonParts{};
        if (hp.points[i].glossy)
          gather_glossy<Grid, kTagged>(grid, scene, hp, i, g, parts, credit);
        else if (limits_.active)
          gather_diffuse<Grid, true, kTagged>(grid, hp, i, g, parts, credit);
        else
          gather_diffuse<Grid, false, kTagged>(grid, hp, i, g, parts, credit);
        gathered_m_[i] = g.m;
        gathered_tau_[i] = g.tau;
        gathered_bias_[i] = static_cast<float>(g.bias);
      }
    };
  };
  const double interval = settings_.progress_interval;
  const bool tagged = split || crediting;
  if (!(tagged ? parallel_chunks(threads_, hchunks, gather(std::true_type{}), cancel, poll, interval)
               : parallel_chunks(threads_, hchunks, gather(std::false_type{}), cancel, poll, interval)))
    return false;
  if (crediting) {  // chunk order: the same sums whichever thread gathered which chunk
    band_credit_.assign(static_cast<size_t>(guide_.slots()) * PhotonGuide::kBins, 0.0);
    for (size_t c = 0; c < hchunks; ++c)
      for (size_t k = 0; k < band_credit_.size(); ++k) band_credit_[k] += chunk_credit_[c][k];
  }
  return true;
}

// The pass's volume photons in their own quantile grid, stored in its cell order (as index_photons).
size_t PhotonPass::index_volume_photons(size_t chunks) {
  volume_traced_.clear();
  for (size_t c = 0; c < chunks; ++c)
    for (const VolumePhoton& v : chunk_volume_[c]) volume_traced_.push_back(v.position);
  const size_t count = volume_traced_.size();
  volume_positions_.resize(count);
  volume_arrivals_.resize(count);
  volume_arrival_bounces_.resize(limits_.active ? count : 0);
  if (count == 0) return 0;
  static const std::vector<double> kNoRadii;
  volume_grid_.build(volume_traced_, kNoRadii, threads_);
  volume_grid_.relabel_in_cell_order(volume_old_of_new_);
  std::vector<uint32_t> new_of_old(count);
  for (size_t i = 0; i < count; ++i) new_of_old[volume_old_of_new_[i]] = static_cast<uint32_t>(i);
  size_t k = 0;
  for (size_t c = 0; c < chunks; ++c)
    for (size_t j = 0; j < chunk_volume_[c].size(); ++j, ++k) {
      const VolumePhoton& v = chunk_volume_[c][j];
      volume_positions_[new_of_old[k]] = v.position;
      volume_arrivals_[new_of_old[k]] = VolumeArrival{v.direction, v.flux, v.beamed};
      if (limits_.active) volume_arrival_bounces_[new_of_old[k]] = chunk_volume_bounces_[c][j];
    }
  return count;
}

// The pass's photon beams indexed, one per kPhotonsPerBeam photons kept or kMinPhotonBeams (the
// same ones in every share of the pass).
void PhotonPass::index_photon_beams(uint64_t pass, size_t chunks) {
  const size_t most = std::max<uint64_t>(kMinPhotonBeams, settings_.photons_per_pass / kPhotonsPerBeam);
  photon_beams_.build(chunk_beams_, chunks, most, mix64(settings_.seed ^ mix64(kPhotonStream + pass)));
}

// Each hit point in a medium: the volume photons within r, each times the phase function from its
// travel direction to the way back along the eye path, summed, times the hit point's weight.
bool PhotonPass::gather_volume(const Scene& scene, std::vector<VolumeHitPoint>& points, std::atomic<bool>& cancel,
                               const std::function<bool()>& poll, PhotonPassCounters& counters) {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = points.size(), chunks = (n + kHitPointChunk - 1) / kHitPointChunk;
  const bool any = !volume_positions_.empty();
  auto work = [&](int, size_t chunk) {
    for (size_t i = chunk * kHitPointChunk; i < std::min(n, (chunk + 1) * kHitPointChunk); ++i) {
      VolumeHitPoint& h = points[i];
      h.m = 0;
      h.tau = Vec3f(0.0f);
      h.pass_bias = 0.0f;
      if (!any) continue;
      const Medium& medium = scene.medium(static_cast<uint32_t>(h.medium));
      const Phase& phase = medium.c.phase;
      const Vec3 center = h.position, back = -Vec3(h.direction);
      const double r2 = h.r2, r = std::sqrt(r2);
      const bool limited = limits_.active;
      const Bounces budget = limited ? limits_.budget(h.chain) : Bounces{};
      Color sum(0.0), sum_d2(0.0);
      uint32_t m = 0;
      volume_grid_.for_each_run_in_box(center - r, center + r, [&](uint32_t begin, uint32_t end) {
        for (uint32_t p = begin; p < end; ++p) {
          const Vec3 d = volume_positions_[p] - center;
          const double d2 = glm::dot(d, d);
          if (d2 > r2 || (limited && !within(volume_arrival_bounces_[p], budget))) continue;
          const VolumeArrival& a = volume_arrivals_[p];
          if (a.beamed && h.beamed_elsewhere) continue;
          ++m;
          const Color f = Color(a.flux) * phase.eval(Vec3(a.direction), back);
          sum += f;
          sum_d2 += f * d2;
        }
      });
      h.m = m;
      BallInside inside;
      if (settings_.volume_boundary && m > 0) {
        const double here = luminance(scene.sigma_s_at(medium, center, Vec3(h.direction)));
        inside = ball_inside(scene, center, r, h.media, here);
        if (medium.varies()) inside.share = ball_share_varying(scene, medium, center, r, Vec3(h.direction), here, inside);
      }
      sum /= inside.share;
      sum_d2 /= inside.share;
      h.tau = Vec3f(sum * Color(h.weight));
      h.pass_bias = static_cast<float>(luminance(bias_sum_in_ball(sum, sum_d2, r2, inside.mean_d2) * Color(h.weight)));
    }
  };
  if (!parallel_chunks(threads_, chunks, work, cancel, poll, settings_.progress_interval)) return false;
  counters.gather_seconds += seconds_since(t0);
  return true;
}

void PhotonPass::keep_band_credit() {
  if (band_credit_.empty()) return;
  pass_credit_.resize(band_credit_.size(), 0.0);
  for (size_t k = 0; k < band_credit_.size(); ++k) pass_credit_[k] += band_credit_[k];
  band_credit_.clear();
}

// The pixel's weight over the gather disc's area: a photon's luminance times it is proportional to
// the share of the pixel's noise its light is part of (radiance is flux over pi r^2).
double PhotonPass::guide_weight(const HitPoints& hp, size_t i) const {
  const HitPoint& h = hp.points[i];
  const uint32_t pixel = hp.shading[h.shading].pixel;
  return pixel < guide_weights_->size() && h.r2 > 0.0 ? (*guide_weights_)[pixel] / h.r2 : 0.0;
}

void PhotonPass::learn_guide() {
  if (!guide_ready_ || pass_credit_.empty()) return;
  guide_.learn(pass_credit_);
  std::fill(pass_credit_.begin(), pass_credit_.end(), 0.0);
}

size_t PhotonPass::photon_bytes() const {
  size_t bytes = 0;
  for (const auto& v : chunk_photons_) bytes += v.capacity() * sizeof(Photon);
  bytes += (traced_positions_.capacity() + positions_.capacity()) * sizeof(Vec3) + arrivals_.capacity() * sizeof(Arrival) +
           arrival_bounces_.capacity() * sizeof(Bounces) + arrival_caustic_.capacity() +
           arrival_origin_.capacity() * sizeof(int32_t);
  for (const auto& v : chunk_caustic_) bytes += v.capacity();
  for (const auto& v : chunk_origin_) bytes += v.capacity() * sizeof(int32_t);
  for (const auto& v : chunk_volume_) bytes += v.capacity() * sizeof(VolumePhoton);
  for (const auto& v : chunk_volume_bounces_) bytes += v.capacity() * sizeof(Bounces);
  bytes += volume_arrival_bounces_.capacity() * sizeof(Bounces);
  bytes += (volume_traced_.capacity() + volume_positions_.capacity()) * sizeof(Vec3) +
           volume_arrivals_.capacity() * sizeof(VolumeArrival) + volume_old_of_new_.capacity() * sizeof(uint32_t);
  return bytes + (old_of_new_.capacity() + new_of_old_.capacity()) * sizeof(uint32_t);
}

size_t PhotonPass::index_bytes() const {
  return quantile_.memory_bytes() + hash_.memory_bytes() + volume_grid_.memory_bytes() + photon_beams_.memory_bytes();
}

size_t PhotonPass::per_hit_point_bytes() const {
  size_t bytes = 0;
  for (const auto& v : m_acc_) bytes += v.capacity() * sizeof(uint32_t);
  for (const auto& v : tau_acc_) bytes += v.capacity() * sizeof(Vec3f);
  for (const auto& v : bias_acc_) bytes += v.capacity() * sizeof(float);
  bytes += gathered_bias_.capacity() * sizeof(float) + gathered_parts_.capacity() * sizeof(PhotonParts);
  for (const auto& v : chunk_credit_) bytes += v.capacity() * sizeof(double);
  bytes += (band_credit_.capacity() + pass_credit_.capacity()) * sizeof(double) + guide_.memory_bytes();
  bytes += gathered_m_.capacity() * sizeof(uint32_t) + gathered_tau_.capacity() * sizeof(Color);
  return bytes + centers_.capacity() * sizeof(Vec3) + radii_.capacity() * sizeof(double);
}

}  // namespace ppm
