// The Beam x Beam estimate (Jarosz et al. 2011, "1D" blur): eye beams (hit_point.h's VolumeBeam)
// against the pass's photon beams (photon_beams.h). Where the two lines pass within r of each
// other, at t_e along the eye beam and t_p along the photon beam, the eye sees
//   flux(t_p) sigma_s phase T(t_e) k(u) / sin(theta),
// u the distance between the lines, theta the angle between them and k the box kernel 1 / (2 r)
// (its 1 / (2 r) and the photon count are applied with the pass, render_context.h).
#include "ppm/photon_pass.h"

#include "base/parallel.h"
#include "ppm/error_estimate.h"
#include "shading/free_path.h"

#include <algorithm>
#include <chrono>

namespace ppm {

namespace {

constexpr size_t kBeamChunk = 256;  // eye beams per work item
// Nearly parallel beams are left out: their 1 / sin(theta) is unbounded, and the pair's share of
// all pairs (a cone of this half-angle) is ~1e-8.
constexpr double kMinSin2 = 1e-8;

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

void PhotonPass::gather_beam(const Scene& scene, VolumeBeam& b) const {
  b.m = 0;
  b.tau = Vec3f(0.0f);
  b.pass_bias = 0.0f;
  if (photon_beams_.size() == 0 || !(b.r2 > 0.0f)) return;
  const double r2 = b.r2, r = std::sqrt(r2);
  const Vec3 origin = b.origin, dir = Vec3(b.direction), back = -dir;
  const Medium& med = scene.medium(static_cast<uint32_t>(b.medium));
  const Phase& phase = med.c.phase;
  const Color sigma_t(b.sigma_t), sigma_s = med.c.sigma_s;
  const bool limited = limits_.active;
  const Bounces budget = limited ? limits_.budget(b.chain) : Bounces{};
  Color sum(0.0), sum_u2(0.0);
  uint32_t m = 0;
  photon_beams_.for_each_near_segment(origin, 1.0 / dir, 0.0, b.length, r, [&](const PhotonBeam& p,
                                                                                const PhotonBeamIndex::Piece& piece) {
    if (p.medium != b.medium) return;
    const Vec3 pd(p.direction), w = origin - p.origin;
    const double c = glm::dot(dir, pd), sin2 = 1.0 - c * c;
    if (!(sin2 > kMinSin2)) return;
    const double d = glm::dot(dir, w), e = glm::dot(pd, w);
    const double te = (c * e - d) / sin2, tp = (e - c * d) / sin2;
    if (te < 0.0 || te > b.length || tp < 0.0 || tp > p.length || !piece.holds(tp, p)) return;
    const Vec3 across = w + te * dir - tp * pd;
    const double u2 = glm::dot(across, across);
    if (u2 > r2 || (limited && !within(p.used, budget))) return;
    const Color tr = transmittance(sigma_t, tp);
    const double reach = glm::dot(Color(p.channel_pdf), tr);
    if (!(reach > 0.0)) return;
    ++m;
    const Color f = Color(p.flux) * tr * (phase.eval(pd, back) / (reach * std::sqrt(sin2))) * sigma_s *
                    transmittance(sigma_t, te);
    sum += f;
    sum_u2 += f * u2;
  });
  b.m = m;
  b.tau = Vec3f(sum * Color(b.weight));
  b.pass_bias = static_cast<float>(luminance(bias_sum_on_line(sum, sum_u2, r2) * Color(b.weight)));
}

}  // namespace ppm
