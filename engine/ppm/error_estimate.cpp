// Per-pixel and image error estimates (see error_estimate.h).
#include "ppm/error_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ppm {
namespace {

// Quantile of the standard normal (Acklam's rational approximation, relative error < 1.2e-9).
double normal_quantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  constexpr double low = 0.02425;
  if (p < low) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - low) return -normal_quantile(1.0 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

}  // namespace

double student_t_quantile(double confidence, double dof) {
  if (!(confidence > 0.0 && confidence < 1.0)) throw std::invalid_argument("confidence must be in (0, 1)");
  if (!(dof >= 1.0)) throw std::invalid_argument("Student's t needs at least one degree of freedom");
  const double p = 0.5 + 0.5 * confidence;
  constexpr double kPi = 3.14159265358979323846;
  if (dof < 1.5) return std::tan(kPi * (p - 0.5));                       // exact for 1
  if (dof < 2.5) return (2.0 * p - 1.0) / std::sqrt(2.0 * p * (1.0 - p));  // exact for 2
  // Cornish-Fisher expansion in 1/dof (Abramowitz & Stegun 26.7.5): within 1% at 3 degrees of
  // freedom and 0.99 confidence, closer above (error_estimate_test.cpp).
  const double z = normal_quantile(p), z2 = z * z;
  const double g1 = z * (z2 + 1.0) / 4.0;
  const double g2 = z * ((5.0 * z2 + 16.0) * z2 + 3.0) / 96.0;
  const double g3 = z * (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) / 384.0;
  const double g4 = z * ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) / 92160.0;
  const double v = dof;
  return z + g1 / v + g2 / (v * v) + g3 / (v * v * v) + g4 / (v * v * v * v);
}

PixelError pixel_error(const PixelErrorStats& s, uint64_t passes, double t, double sampling_variance) {
  PixelError e;
  e.value = s.value.mean;
  e.bias = s.bias.mean;
  if (passes < kMinErrorPasses) {
    e.noise = std::numeric_limits<double>::infinity();
    return e;
  }
  const double n = static_cast<double>(passes), b = s.bias.mean, bias_variance = s.bias.variance_of_mean(n);
  // A bias estimate within two of its standard deviations of 0 is taken as none (a significance
  // test); a larger one is shrunk by its variance (see PixelError).
  e.bias = b * b > 4.0 * bias_variance ? std::copysign(std::sqrt(b * b - bias_variance), b) : 0.0;
  e.bias_sd = std::sqrt(bias_variance);
  e.sd = std::sqrt(std::max(s.value.variance_of_mean(n), sampling_variance));
  e.noise = t * e.sd;
  return e;
}

namespace {

// The q-quantile of the values added, from a histogram on a log scale (2.3% wide bins from 1e-6 to
// 1e3; outside, the ends): no copy of a value per pixel.
class LogQuantile {
 public:
  void add(double v) {
    const double x = std::log10(std::max(v, kLow)) - std::log10(kLow);
    ++bins_[std::min(kBins - 1, static_cast<size_t>(std::max(0.0, x * kPerDecade)))];
    ++count_;
  }
  double quantile(double q) const {
    const double target = q * static_cast<double>(count_);
    double seen = 0.0;
    for (size_t b = 0; b < kBins; ++b) {
      seen += static_cast<double>(bins_[b]);
      if (seen >= target) return kLow * std::pow(10.0, (static_cast<double>(b) + 1.0) / kPerDecade);  // bin's top
    }
    return std::numeric_limits<double>::infinity();
  }
  bool empty() const { return count_ == 0; }

 private:
  static constexpr double kLow = 1e-6, kPerDecade = 100.0;
  static constexpr size_t kBins = 900;
  std::vector<uint64_t> bins_ = std::vector<uint64_t>(kBins, 0);
  uint64_t count_ = 0;
};

}  // namespace

ImageError image_error(const std::vector<PixelErrorStats>& pixels, const ErrorPasses& counts, double confidence,
                       const std::vector<float>& sampling_variance) {
  ImageError out;
  out.confidence = confidence;
  double sum_value = 0.0, sum_bias = 0.0, sum_sd = 0.0, sum_absolute = 0.0, variance = 0.0, sum_aliasing = 0.0;
  auto sampling = [&](size_t p) { return sampling_variance.empty() ? 0.0 : double(sampling_variance[p]); };
  double passes = 0.0;
  StudentTByPasses t_of(confidence);
  for (size_t p = 0; p < pixels.size(); ++p) {
    const PixelErrorStats& s = pixels[p];
    const uint64_t n = counts.of(p);
    const PixelError e = pixel_error(s, n, t_of(n), sampling(p));
    const double rms = e.rms();
    if (n >= kMinErrorPasses)
      sum_aliasing += std::sqrt(std::max(0.0, sampling(p) - s.value.variance_of_mean(static_cast<double>(n))));
    sum_value += std::fabs(e.value);
    sum_bias += std::fabs(e.bias);
    sum_sd += e.sd;
    sum_absolute += e.mean_absolute();
    // The variance of the pixel's estimate, taken as its rms's: its bias part's (var(bias)) and its
    // sd part's (an sd estimated from n samples varies by sd^2 / (2 (n - 1))), each weighted by
    // its share of the rms.
    if (rms > 0.0 && n >= kMinErrorPasses)
      variance += (e.bias * e.bias * e.bias_sd * e.bias_sd + e.sd * e.sd * e.sd * e.sd / (2.0 * (n - 1.0))) /
                  (rms * rms);
    passes = std::max(passes, static_cast<double>(n));
  }
  if (passes < kMinErrorPasses || !(sum_value > 0.0)) {  // nothing yet, or a black image: no relative error
    const double none = passes < kMinErrorPasses ? std::numeric_limits<double>::infinity() : 0.0;
    out.relative = out.bias = out.noise = out.bound = out.pixel_p95 = out.anti_aliasing = none;
    return out;
  }
  out.bias = sum_bias / sum_value;
  out.noise = sum_sd / sum_value;
  out.anti_aliasing = sum_aliasing / sum_value;
  out.relative = sum_absolute / sum_value;
  out.bound = out.relative + student_t_quantile(confidence, passes - 1.0) * std::sqrt(variance) / sum_value;
  const double bright = 0.05 * sum_value / static_cast<double>(pixels.size());
  LogQuantile relative;
  for (size_t p = 0; p < pixels.size(); ++p) {
    const uint64_t n = counts.of(p);
    const PixelError e = pixel_error(pixels[p], n, t_of(n), sampling(p));
    if (std::fabs(e.value) >= bright) relative.add(e.bound() / std::fabs(e.value));
  }
  out.pixel_p95 = relative.empty() ? 0.0 : relative.quantile(0.95);
  return out;
}

}  // namespace ppm
