// Homogeneous free paths: Cycles' channel pick and chromatic distance sampling (free_path.h).
#include "shading/free_path.h"

namespace ppm {

ChannelPick pick_channel(const Color& albedo, const Color& throughput, double& u) {
  ChannelPick pick;
  const Color weights = glm::abs(throughput * albedo);
  const double sum = weights.x + weights.y + weights.z;
  if (sum > 0.0 && std::isfinite(sum)) pick.pdf = weights / sum;
  u = safe_uniform(u);
  // The last channel with a probability takes what rounding leaves at the top.
  double below = 0.0, last_below = 0.0;
  int last = 0;
  for (int c = 0; c < 3; ++c) {
    if (!(pick.pdf[c] > 0.0)) continue;
    if (u < below + pick.pdf[c]) {
      pick.channel = c;
      u = safe_uniform((u - below) / pick.pdf[c]);
      return pick;
    }
    last = c;
    last_below = below;
    below += pick.pdf[c];
  }
  pick.channel = last;
  u = safe_uniform((u - last_below) / pick.pdf[last]);
  return pick;
}

// pick_channel by the medium's albedo (Cycles: 1 where sigma_t is 0, so that a clear channel can be
// picked, and then passes) and the path's throughput (non-finite channels as 0).
static ChannelPick pick_medium_channel(const Color& sigma_t, const Color& sigma_s, const Color& throughput,
                                       double& u_channel) {
  Color albedo(1.0);
  for (int c = 0; c < 3; ++c)
    if (sigma_t[c] > 0.0) albedo[c] = sigma_s[c] / sigma_t[c];
  const Color safe_throughput(std::isfinite(throughput.x) ? throughput.x : 0.0,
                              std::isfinite(throughput.y) ? throughput.y : 0.0,
                              std::isfinite(throughput.z) ? throughput.z : 0.0);
  return pick_channel(albedo, safe_throughput, u_channel);
}

FreePathSample sample_free_path(const Color& sigma_t_in, const Color& sigma_s_in, const Color& throughput,
                                double segment, double u_channel, double u_distance) {
  // A scattering coefficient above the extinction is cut to it (the albedo stays within [0, 1]).
  const Color sigma_t = safe_coefficients(sigma_t_in);
  const Color sigma_s = glm::min(safe_coefficients(sigma_s_in), sigma_t);
  const double d = safe_distance(segment);
  if (sigma_s == Color(0.0)) return {FreePathEvent::Exit, d, transmittance(sigma_t, d)};

  const ChannelPick pick = pick_medium_channel(sigma_t, sigma_s, throughput, u_channel);
  const double sigma = sigma_t[pick.channel];
  const double t = sigma > 0.0 ? -std::log1p(-safe_uniform(u_distance)) / sigma : kInf;

  // Both densities are positive in finite arithmetic: the picked channel has pdf > 0 and sigma t
  // <= 37.5 (or it passes with sigma d <= 37.5). Where t overflows (sigma near the smallest double,
  // an infinite segment) they are 0, and the path carries nothing on.
  const auto divided = [](const Color& numerator, double density) {
    return density > 0.0 ? numerator / density : Color(0.0);
  };
  if (t < d) {
    const Color tr = transmittance(sigma_t, t);
    return {FreePathEvent::Scatter, t, divided(sigma_s * tr, glm::dot(pick.pdf, sigma_t * tr)), pick.pdf};
  }
  const Color tr = transmittance(sigma_t, d);
  return {FreePathEvent::Exit, d, divided(tr, glm::dot(pick.pdf, tr)), pick.pdf};
}

double EquiangularTarget::sample(double d, double u) const {
  const double a = std::atan2(-foot, height);
  return glm::clamp(foot + height * std::tan(a + u * span(d)), 0.0, d);
}

double EquiangularTarget::pdf(double d, double t) const {
  const double angle = span(d), x = t - foot;
  return angle > 0.0 ? height / (angle * (height * height + x * x)) : 0.0;
}

FreePathSample sample_free_path_within(const Color& sigma_t_in, const Color& sigma_s_in, const Color& throughput,
                                       double segment, double u_channel, double u_distance,
                                       const EquiangularTarget* toward) {
  const Color sigma_t = safe_coefficients(sigma_t_in);
  const Color sigma_s = glm::min(safe_coefficients(sigma_s_in), sigma_t);
  const double d = safe_distance(segment);
  FreePathSample out{FreePathEvent::Exit, d, Color(0.0)};
  if (sigma_s == Color(0.0) || !(d > 0.0)) return out;
  const ChannelPick pick = pick_medium_channel(sigma_t, sigma_s, throughput, u_channel);
  out.channel_pdf = pick.pdf;
  // Each channel's truncated density at t: sigma e^(-sigma t) / (1 - e^(-sigma d)), or 1 / d.
  const auto density = [&](int c, double t) {
    const double s = sigma_t[c];
    if (!(s > 0.0)) return std::isfinite(d) ? 1.0 / d : 0.0;
    return s * std::exp(-s * t) / -std::expm1(-s * d);
  };
  const bool mixed = toward != nullptr && toward->usable(d);
  double u = safe_uniform(u_distance);
  const bool equiangular = mixed && u < 0.5;
  if (mixed) u = equiangular ? 2.0 * u : 2.0 * u - 1.0;
  const double s = sigma_t[pick.channel];
  double t;
  if (equiangular)
    t = toward->sample(d, u);
  else if (s > 0.0)
    t = -std::log1p(u * std::expm1(-s * d)) / s;
  else if (std::isfinite(d))
    t = u * d;
  else
    return out;
  t = std::min(t, d);
  double pdf = 0.0;
  for (int c = 0; c < 3; ++c)
    if (pick.pdf[c] > 0.0) pdf += pick.pdf[c] * density(c, t);
  if (mixed) pdf = 0.5 * (pdf + toward->pdf(d, t));
  if (!(pdf > 0.0) || !std::isfinite(t)) return out;
  out.event = FreePathEvent::Scatter;
  out.distance = t;
  out.weight = sigma_s * transmittance(sigma_t, t) / pdf;
  return out;
}

}  // namespace ppm
