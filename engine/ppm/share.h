// A share of a still's passes, and the merge of shares: one still rendered on many machines.
//
// With the global radius schedule (radius_schedule.h) pass i's estimate depends only on the scene,
// the settings, the seed and i: each machine renders a range of passes (settings.first_pass) and
// returns a Share, the mean of its passes per pixel and the error estimate's moments
// (error_estimate.h). Merging shares is exact: the pixel means combine weighted by their pass
// counts, the moments by Chan et al.'s pairwise update, so the merge of N shares of K passes is
// the image, and the error estimate, of one render of the N K passes, bar float rounding.
// Shares of one still have the same size, seed, alpha and photons per pass, and no pass twice.
#pragma once

#include "ppm/error_estimate.h"

#include <cstdint>
#include <vector>

namespace ppm {

struct PassRange {
  uint64_t first = 0, count = 0;  // passes first .. first + count - 1
};

struct Share {
  int width = 0, height = 0;
  uint64_t seed = 0, photons_per_pass = 0;
  double alpha = 0.0;
  std::vector<PassRange> ranges;        // sorted, disjoint
  std::vector<float> image;             // per pixel, top row first: RGBA, the passes' mean (RGB premultiplied)
  std::vector<PixelErrorStats> errors;  // per pixel, top row first: the passes' moments
  std::vector<float> seen;              // with light passes: per pixel Emit RGB, Env RGB means; else empty

  uint64_t passes() const;
  size_t pixels() const { return static_cast<size_t>(width) * height; }
  // Throws std::invalid_argument if the arrays do not match the size or the ranges overlap.
  void validate() const;
};

// Adds `part`'s passes to `total` (an empty total becomes a copy). Throws std::invalid_argument
// naming what differs if they are not shares of one still, or if they share a pass.
void merge_into(Share& total, const Share& part);

// The error estimate of a share's image (error_estimate.h): the image's, and per pixel, top row
// first, bias, noise (at `confidence`) and luminance.
ImageError share_error(const Share& share, double confidence);
std::vector<float> share_error_image(const Share& share, double confidence);

}  // namespace ppm
