// A per-pixel estimate of the image's error, bias and noise apart, made from the passes themselves
// (after Hachisuka, Jarosz & Jensen 2010, "A Progressive Error Estimation Framework for Photon
// Density Estimation"; the bias term is our own single-sum form, derived below).
//
// The estimate is the mean of per-pass estimates. tau / r^2 is unchanged by the radius update
// (both scale by (n + alpha m) / (n + m)), so (tau + tau_m) / (pi r^2 N_emitted) is exactly the
// mean over passes j of y_j = flux_j / (pi r_j^2 N_j), the flux gathered in pass j at its radius
// r_j; direct and seen light are means over passes too. So:
//   noise: the sample variance of the pixel's pass values y_j, over the passes, gives the
//     variance of their mean; times Student's t at the chosen confidence, the noise's bound.
//   bias: a uniform disc of radius r averages L over the disc: E[y] - L = r^2 Lap(L) / 8 + O(r^4).
//     Weighting each photon of pass j by 3 (2 d^2 / r_j^2 - 1), d its distance, instead of 1 gives
//     an estimate b_j with E[b_j] = r_j^2 Lap(L) / 8 exactly where L is quadratic (the weights
//     integrate to 0 over the disc, and to r^2 / 8 times the Laplacian against a quadratic), so
//     the mean of b_j estimates the bias of the mean of y_j. Where L has an edge (a caustic's,
//     a shadow's) the quadratic model is off: bench/README gives where it fails.
//   anti-aliasing (fixed hit points): with the same eye samples every pass, their mean differs
//     from the pixel's whole footprint by an error no pass removes. Its variance is that of the
//     mean of the pixel's n samples, s^2 / n, s^2 the spread of the samples' current values; those
//     carry the photons' noise too (E[s^2 / n] = anti-aliasing + noise variance where the samples'
//     noises are independent), so the pixel's variance is the larger of s^2 / n and the passes'
//     noise variance. At 1 sample per pixel there is no spread to measure, and streamed hit points
//     keep no per-sample light: not estimated there.
// All in luminance (Rec. 709 weights), the pixel's premultiplied value.
#pragma once

#include "math/types.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ppm {

// The bias weight of a photon at squared distance d2 from a hit point of radius^2 r2: the flux
// it adds, times this, summed over the pass and scaled as the flux is, is b_j (see above).
inline double bias_weight(double d2, double r2) { return 3.0 * (2.0 * d2 / r2 - 1.0); }
// The same summed over photons from their flux and their flux times d2 (no division per photon).
inline Color bias_sum(const Color& flux, const Color& flux_d2, double r2) { return flux_d2 * (6.0 / r2) - flux * 3.0; }

// The same for a hit point in a medium, its photons gathered in a ball of radius r (progressive.h's
// volume estimate). The ball's average is biased by r^2 Lap(L) / 10 + O(r^4) where L is quadratic
// (E[x_i^2] = r^2 / 5 over the ball). A weight a (d^2 / r^2 - c) integrates to 0 for c = E[d^2] /
// r^2 = 3 / 5, and against x_i^2 to a (E[d^2 x_i^2] / r^2 - 3 r^2 / 25) = a r^2 (1 / 7 - 3 / 25)
// (E[d^4] = 3 r^4 / 7, a third of it per axis), which is r^2 / 5 for a = 35 / 4. (On the disc the
// same steps give 3 (2 d^2 / r^2 - 1), bias_weight above.)
inline double bias_weight_in_ball(double d2, double r2) { return (35.0 * d2 / r2 - 21.0) / 4.0; }
// `mean_d2`: E[d^2] / r^2 over the part of the ball photons can reach (3/5: all of it), so that
// a constant density inside a ball cut by a medium's boundary reads as no curvature.
inline Color bias_sum_in_ball(const Color& flux, const Color& flux_d2, double r2, double mean_d2 = 0.6) {
  return flux_d2 * (35.0 / (4.0 * r2)) - flux * (35.0 / 4.0 * mean_d2);
}

// The same for an eye beam, its photon beams weighed by a 1-D box kernel over their distance u
// across it (photon_pass_beams.cpp): the box's average is biased by r^2 L'' / 6 (E[u^2] = r^2 / 3);
// a weight a (u^2 / r^2 - 1/3) integrates to 0, and against u^2 / 2 to a r^2 (1/5 - 1/9) / 2, which
// is r^2 / 6 for a = 15 / 4.
inline Color bias_sum_on_line(const Color& flux, const Color& flux_u2, double r2) {
  return flux_u2 * (15.0 / (4.0 * r2)) - flux * (5.0 / 4.0);
}

// Running mean and sum of squared deviations in float (Welford: stable over thousands of passes,
// where sums of squares would cancel).
struct RunningMoments {
  float mean, m2;
  void add(double x, float count) {
    const double delta = x - mean;
    mean = static_cast<float>(mean + delta / count);
    m2 = static_cast<float>(m2 + delta * (x - mean));
  }
  // The variance of the mean of `count` samples.
  double variance_of_mean(double count) const { return std::max(0.0, double(m2)) / ((count - 1.0) * count); }
};

// One pixel's pass values y_j and bias estimates b_j: 16 bytes a pixel. How many passes it has is
// the render's count (ErrorPasses), not kept per pixel.
struct PixelErrorStats {
  RunningMoments value, bias;

  // Pass number `pass` (1 for the first).
  void add(double value_sample, double bias_sample, uint64_t pass) {
    value.add(value_sample, static_cast<float>(pass));
    bias.add(bias_sample, static_cast<float>(pass));
  }
};
static_assert(sizeof(PixelErrorStats) == 16, "PixelErrorStats grew");

// The passes each pixel's statistics hold: `passes`, and one more for the pixels before
// `ahead_end` (the bands of a stochastic or streamed pass in progress already folded in).
struct ErrorPasses {
  uint64_t passes = 0;
  size_t ahead_end = 0;
  uint64_t of(size_t pixel) const { return passes + (pixel < ahead_end ? 1 : 0); }
};

// A pixel's estimated error in luminance. The mean of the b_j is noisy itself, and its magnitude
// is then too large on average: E[mean^2] = bias^2 + var(mean), so the bias is taken as
// sqrt(max(0, mean^2 - var(mean))) with the mean's sign.
struct PixelError {
  double value = 0.0;    // the pixel's luminance
  double bias = 0.0;     // expected (image minus truth)
  double bias_sd = 0.0;  // standard deviation of the bias estimate
  double sd = 0.0;       // standard deviation of the pixel's value (the noise, anti-aliasing included)
  double noise = 0.0;    // half-width of the noise at the confidence asked for: t sd
  // At the confidence asked for, the error is at most this (Hachisuka et al.'s bound).
  double bound() const { return std::fabs(bias) + noise; }
  // The root mean square error, and the mean absolute error (of a normal error: the folded
  // normal's mean, 0.80 sd for noise alone).
  double rms() const { return std::sqrt(bias * bias + sd * sd); }
  double mean_absolute() const {
    const double b = std::fabs(bias);
    if (!(sd > 0.0)) return b;
    return sd * 0.7978845608028654 * std::exp(-0.5 * b * b / (sd * sd)) + b * std::erf(b / (sd * 1.4142135623730951));
  }
};

// A pixel's error as the 3 floats Renderer::error() and Share::error() give: bias, noise, luminance.
inline void write_error_channels(const PixelError& e, float* out) {
  out[0] = saturated_float(e.bias);
  out[1] = saturated_float(e.noise);
  out[2] = saturated_float(e.value);
}

// Two-sided quantile of Student's t with `dof` degrees of freedom: |T| <= t with probability
// `confidence` (in (0, 1)). dof >= 1.
double student_t_quantile(double confidence, double dof);

// Passes before an estimate means anything: fewer give no noise estimate (infinite bound).
constexpr uint64_t kMinErrorPasses = 2;

// `t` is student_t_quantile(confidence, passes - 1); `sampling_variance` the variance of the mean of
// the pixel's fixed eye samples (anti-aliasing, above; 0: none).
PixelError pixel_error(const PixelErrorStats& s, uint64_t passes, double t, double sampling_variance = 0.0);

// The t of each pixel's pass count, asked once per count as the pixels are walked (a stochastic
// pass in progress leaves two counts).
class StudentTByPasses {
 public:
  explicit StudentTByPasses(double confidence) : confidence_(confidence) {}
  double operator()(uint64_t passes) {
    if (passes != passes_ && passes >= kMinErrorPasses) {
      passes_ = passes;
      t_ = student_t_quantile(confidence_, static_cast<double>(passes) - 1.0);
    }
    return t_;
  }

 private:
  double confidence_;
  uint64_t passes_ = 0;
  double t_ = 0.0;
};

// The image's error, relative to its mean luminance (a relative L1 norm: dark pixels count by the
// error they add, not by their ratio): `relative` estimates the mean absolute error over the
// pixels, `bound` is its upper confidence bound (over the uncertainty of the pixels' estimates;
// the pixels are many, so it is close), and
// `pixel_p95` the 95th percentile of the pixels' own bounds relative to their values, among the
// pixels at least 5% as bright as the mean. What the quadratic bias model misses (edges) is in
// none of them. All inf before kMinErrorPasses passes.
struct ImageError {
  double relative = 0.0;
  double bias = 0.0;   // the part of `relative` that is bias: sum |bias| / sum of values
  double noise = 0.0;  // and noise: sum of the values' sd / sum of values
  double anti_aliasing = 0.0;  // of which the eye samples' spread beyond the passes' noise (fixed hit points)
  double bound = 0.0;  // what target_error compares with
  double pixel_p95 = 0.0;
  double confidence = 0.0;
};

// `sampling_variance`: per pixel (pixel_error's), or empty.
ImageError image_error(const std::vector<PixelErrorStats>& pixels, const ErrorPasses& passes, double confidence,
                       const std::vector<float>& sampling_variance = {});

}  // namespace ppm
