// Shares of a still's passes and their merge (see share.h).
#include "ppm/share.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ppm {
namespace {

void fail(const std::string& m) { throw std::invalid_argument("share: " + m); }

// The mean and the sum of squared deviations of two sets of na and nb values (Chan, Golub &
// LeVeque 1979), in double.
RunningMoments merged(const RunningMoments& a, double na, const RunningMoments& b, double nb) {
  const double n = na + nb, delta = double(b.mean) - double(a.mean);
  return RunningMoments{static_cast<float>(a.mean + delta * nb / n),
                        static_cast<float>(double(a.m2) + double(b.m2) + delta * delta * na * nb / n)};
}

std::vector<PassRange> merged_ranges(std::vector<PassRange> ranges, const std::vector<PassRange>& more) {
  ranges.insert(ranges.end(), more.begin(), more.end());
  std::sort(ranges.begin(), ranges.end(), [](const PassRange& a, const PassRange& b) { return a.first < b.first; });
  for (size_t i = 1; i < ranges.size(); ++i)
    if (ranges[i].first < ranges[i - 1].first + ranges[i - 1].count)
      fail("pass " + std::to_string(ranges[i].first) + " is in both shares (a pass may be merged once)");
  return ranges;
}

}  // namespace

uint64_t Share::passes() const {
  uint64_t n = 0;
  for (const PassRange& r : ranges) n += r.count;
  return n;
}

void Share::validate() const {
  if (width < 1 || height < 1) fail("width and height must be positive");
  if (image.size() != pixels() * 4) fail("image must hold 4 floats a pixel");
  if (errors.size() != pixels()) fail("moments must hold one entry a pixel");
  if (!seen.empty() && seen.size() != pixels() * 6) fail("light passes must hold 6 floats a pixel, or none");
  for (const PassRange& r : ranges)
    if (r.count == 0) fail("a pass range is empty");
  merged_ranges(ranges, {});
}

void merge_into(Share& total, const Share& part) {
  part.validate();
  if (total.ranges.empty()) {
    total = part;
    return;
  }
  if (total.width != part.width || total.height != part.height)
    fail("sizes differ: " + std::to_string(total.width) + "x" + std::to_string(total.height) + " and " +
         std::to_string(part.width) + "x" + std::to_string(part.height));
  if (total.seed != part.seed) fail("seeds differ (one still's shares have one seed and distinct passes)");
  if (total.alpha != part.alpha) fail("alpha differs");
  if (total.photons_per_pass != part.photons_per_pass) fail("photons_per_pass differs");
  if (total.seen.empty() != part.seen.empty()) fail("one share has light passes and the other not");
  std::vector<PassRange> ranges = merged_ranges(total.ranges, part.ranges);
  const double na = static_cast<double>(total.passes()), nb = static_cast<double>(part.passes());
  const double wb = nb / (na + nb);
  auto mix = [wb](std::vector<float>& a, const std::vector<float>& b) {
    for (size_t i = 0; i < a.size(); ++i) a[i] = static_cast<float>(a[i] + (double(b[i]) - a[i]) * wb);
  };
  mix(total.image, part.image);
  mix(total.seen, part.seen);
  for (size_t p = 0; p < total.errors.size(); ++p) {
    PixelErrorStats& a = total.errors[p];
    const PixelErrorStats& b = part.errors[p];
    a.value = merged(a.value, na, b.value, nb);
    a.bias = merged(a.bias, na, b.bias, nb);
  }
  total.ranges = std::move(ranges);
}

ImageError share_error(const Share& share, double confidence) {
  return image_error(share.errors, ErrorPasses{share.passes(), 0}, confidence);
}

std::vector<float> share_error_image(const Share& share, double confidence) {
  std::vector<float> out(share.pixels() * 3);
  const uint64_t n = share.passes();
  const double t = n >= kMinErrorPasses ? student_t_quantile(confidence, static_cast<double>(n) - 1.0) : 0.0;
  for (size_t p = 0; p < share.pixels(); ++p) write_error_channels(pixel_error(share.errors[p], n, t), &out[3 * p]);
  return out;
}

}  // namespace ppm
