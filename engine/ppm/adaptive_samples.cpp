// Adaptive eye sampling (see adaptive_samples.h).
#include "ppm/adaptive_samples.h"

#include <algorithm>
#include <cmath>

namespace ppm {

void allocate_eye_samples(const std::vector<PixelErrorStats>& pixels, uint64_t passes, int max_samples,
                          std::vector<uint8_t>& samples) {
  samples.assign(pixels.size(), 1);
  if (passes < 2 || max_samples <= 1) return;
  const double n = static_cast<double>(passes);
  auto sigma = [n](const PixelErrorStats& s) { return std::sqrt(std::max(0.0, double(s.value.m2)) / (n - 1.0)); };
  double sum = 0.0;
  for (const PixelErrorStats& s : pixels) sum += sigma(s);
  const double mean = sum / static_cast<double>(std::max<size_t>(pixels.size(), 1));
  if (!(mean > 0.0)) return;
  for (size_t p = 0; p < pixels.size(); ++p)
    samples[p] = static_cast<uint8_t>(std::clamp(std::ceil(sigma(pixels[p]) / mean), 1.0, double(max_samples)));
}

}  // namespace ppm
