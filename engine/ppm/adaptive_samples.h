// Adaptive eye sampling for stochastic hit points: where a pixel's pass values spread most (the
// error estimate's statistics, error_estimate.h), its next pass draws more eye samples. With n_p
// samples, a pass value's eye-side variance (anti-aliasing, glossy and lens sampling, the direct
// light's sample) falls as 1 / n_p, and the image's summed variance sum_p sigma_p^2 / n_p for a
// given total is least with n_p proportional to sigma_p. So n_p = ceil(sigma_p / mean sigma),
// clamped to [1, max_samples]: pixels noisier than the average get more. The photons' noise, shared
// by a pixel's samples (they gather nearly the same photons), does not fall with n_p: whether it
// pays at equal time is measured (bench/run.py adaptive).
#pragma once

#include "ppm/error_estimate.h"

#include <cstdint>
#include <vector>

namespace ppm {

// Per pixel, the eye samples of the next pass, from `passes` passes of statistics (at least 2).
void allocate_eye_samples(const std::vector<PixelErrorStats>& pixels, uint64_t passes, int max_samples,
                          std::vector<uint8_t>& samples);

}  // namespace ppm
