// The beam radiance estimate (PhotonPass::gather_beams; hit_point.h's VolumeBeam).
#include "ppm/photon_pass.h"

#include "base/parallel.h"
#include "ppm/error_estimate.h"
#include "shading/free_path.h"

#include <algorithm>
#include <chrono>

namespace ppm {

namespace {

// A beam is searched piece by piece (photons counted in the piece their projection falls in), each
// piece's box widened by r. A query's fixed cost (slab lookups, rows) outweighs the photons its
// box holds beyond the cylinder up to pieces of about 8r (fog_caustic: the gather 3.3 s in 20
// passes at 2r, 2.4 at 4r, 2.2 at 8r and 16r, 2.5 at 32r). A long beam at a tiny radius takes
// longer pieces, so that its queries stay bounded.
constexpr double kPieceRadii = 8.0;
constexpr double kMaxPieces = 256.0;
constexpr size_t kBeamChunk = 256;  // beams per work item: each is many queries

}  // namespace

bool PhotonPass::gather_beams(const Scene& scene, std::vector<VolumeBeam>& beams, std::atomic<bool>& cancel,
                              const std::function<bool()>& poll, PhotonPassCounters& counters) {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = beams.size(), chunks = (n + kBeamChunk - 1) / kBeamChunk;
  auto work = [&](int, size_t chunk) {
    for (size_t i = chunk * kBeamChunk; i < std::min(n, (chunk + 1) * kBeamChunk); ++i)
      gather_beam(scene, beams[i]);
  };
  if (!parallel_chunks(threads_, chunks, work, cancel, poll, settings_.progress_interval)) return false;
  counters.gather_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return true;
}

// Each photon counts in the piece its projection on the beam falls in, once; its distance across
// the beam decides whether it is inside.
void PhotonPass::gather_beam(const Scene& scene, VolumeBeam& b) const {
  b.m = 0;
  b.tau = Vec3f(0.0f);
  b.pass_bias = 0.0f;
  if (volume_positions_.empty() || !(b.r2 > 0.0f)) return;
  const double r2 = b.r2, r = std::sqrt(r2);
  const Vec3 origin = b.origin, dir = Vec3(b.direction), back = -dir;
  Aabb reach = volume_bounds_;
  reach.lo -= r;
  reach.hi += r;
  double begin, end;
  slab_interval(reach, origin, 1.0 / dir, b.length, begin, end);
  if (!(begin <= end)) return;
  const Phase& phase = scene.medium(static_cast<uint32_t>(b.medium)).c.phase;
  const Color sigma_t(b.sigma_t);
  const bool limited = limits_.active;
  const Bounces budget = limited ? limits_.budget(b.chain) : Bounces{};
  const double step = std::max(kPieceRadii * r, (end - begin) / kMaxPieces);
  const auto pieces = static_cast<uint32_t>(std::max(1.0, std::ceil((end - begin) / step)));
  Color sum(0.0), sum_d2(0.0);
  uint32_t m = 0;
  for (uint32_t k = 0; k < pieces; ++k) {
    const double a = begin + k * step, z = k + 1 == pieces ? end : begin + (k + 1) * step;
    const Vec3 p0 = origin + a * dir, p1 = origin + z * dir;
    const bool first = k == 0, last = k + 1 == pieces;
    volume_grid_.for_each_run_in_box(glm::min(p0, p1) - r, glm::max(p0, p1) + r, [&](uint32_t from, uint32_t to) {
      for (uint32_t p = from; p < to; ++p) {
        const Vec3 d = volume_positions_[p] - origin;
        const double t = glm::dot(d, dir);
        if ((t < a && !first) || (t >= z && !last) || t < 0.0 || t > b.length) continue;
        const double d2 = std::max(0.0, glm::dot(d, d) - t * t);
        if (d2 > r2 || (limited && !within(volume_arrival_bounces_[p], budget))) continue;
        const VolumeArrival& arrival = volume_arrivals_[p];
        ++m;
        const Color f = Color(arrival.flux) * (phase.eval(Vec3(arrival.direction), back)) * transmittance(sigma_t, t);
        sum += f;
        sum_d2 += f * d2;
      }
    });
  }
  b.m = m;
  b.tau = Vec3f(sum * Color(b.weight));
  b.pass_bias = static_cast<float>(luminance(bias_sum(sum, sum_d2, r2) * Color(b.weight)));
}

}  // namespace ppm
