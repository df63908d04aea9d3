// Photon guiding (see photon_guide.h).
#include "ppm/photon_guide.h"

#include "math/sampling.h"

#include <algorithm>
#include <cmath>

namespace ppm {

void PhotonGuide::reset(const std::vector<Light>& lights) {
  slot_of_.assign(lights.size(), -1);
  frames_.clear();
  for (size_t i = 0; i < lights.size(); ++i) {
    if (!guidable(lights[i])) continue;
    slot_of_[i] = slots();
    Frame f{emits_into_hemisphere(lights[i]), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), false};
    if (f.hemisphere) {
      f.n = lights[i].direction;
      make_basis(f.n, f.t, f.b);
    }
    frames_.push_back(f);
  }
  importance_.assign(frames_.size() * kBins, 0.0);
  cdf_.assign(frames_.size() * (kBins + 1), 0.0);
  for (size_t s = 0; s < frames_.size(); ++s)
    for (int b = 0; b <= kBins; ++b) cdf_[s * (kBins + 1) + b] = static_cast<double>(b) / kBins;
}

Vec3 PhotonGuide::sample(int slot, double u1, double u2, uint32_t& bin, double& ratio) const {
  const double* cdf = &cdf_[static_cast<size_t>(slot) * (kBins + 1)];
  const int b = static_cast<int>(std::upper_bound(cdf + 1, cdf + kBins + 1, u1) - (cdf + 1));
  bin = static_cast<uint32_t>(std::min(b, kBins - 1));
  const double p = cdf[bin + 1] - cdf[bin];
  // Uniform within the bin (u1's place in it, and u2): equal-area rings in z, sectors in phi.
  const double within = p > 0.0 ? std::clamp((u1 - cdf[bin]) / p, 0.0, 1.0) : 0.5;
  const Frame& f = frames_[slot];
  const int ring = static_cast<int>(bin) / kSectors, sector = static_cast<int>(bin) % kSectors;
  const double z_low = f.hemisphere ? 0.0 : -1.0;
  const double z = z_low + (1.0 - z_low) * (ring + within) / kRings;
  const double phi = 2.0 * kPi * (sector + u2) / kSectors;
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  ratio = p * kBins;
  return glm::normalize(s * std::cos(phi) * f.t + s * std::sin(phi) * f.b + z * f.n);
}

uint32_t PhotonGuide::bin_of(int slot, const Vec3& d) const {
  const Frame& f = frames_[slot];
  const double z_low = f.hemisphere ? 0.0 : -1.0;
  const double z = std::clamp(glm::dot(d, f.n), z_low, 1.0);
  const int ring = std::min(kRings - 1, static_cast<int>((z - z_low) / (1.0 - z_low) * kRings));
  double phi = std::atan2(glm::dot(d, f.b), glm::dot(d, f.t));
  if (phi < 0.0) phi += 2.0 * kPi;
  const int sector = std::min(kSectors - 1, static_cast<int>(phi / (2.0 * kPi) * kSectors));
  return static_cast<uint32_t>(ring * kSectors + sector);
}

void PhotonGuide::learn(const std::vector<double>& credit) {
  for (int s = 0; s < slots(); ++s) {
    const double* c = &credit[static_cast<size_t>(s) * kBins];
    auto usable = [](double x) { return x > 0.0 && std::isfinite(x) ? x : 0.0; };
    double total = 0.0;
    for (int b = 0; b < kBins; ++b) total += usable(c[b]);
    if (!(total > 0.0)) continue;
    double* importance = &importance_[static_cast<size_t>(s) * kBins];
    double sum = 0.0;
    for (int b = 0; b < kBins; ++b) sum += importance[b] += usable(c[b]) / total;  // every pass counts alike
    double* cdf = &cdf_[static_cast<size_t>(s) * (kBins + 1)];
    cdf[0] = 0.0;
    for (int b = 0; b < kBins; ++b)
      cdf[b + 1] = cdf[b] + (1.0 - kUniformShare) * importance[b] / sum + kUniformShare / kBins;
    cdf[kBins] = 1.0;
    frames_[s].learned = true;
  }
}

std::vector<double> PhotonGuide::probabilities(int slot) const {
  std::vector<double> p(kBins);
  const double* cdf = &cdf_[static_cast<size_t>(slot) * (kBins + 1)];
  for (int b = 0; b < kBins; ++b) p[b] = cdf[b + 1] - cdf[b];
  return p;
}

}  // namespace ppm
