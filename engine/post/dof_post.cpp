// Depth-of-field post-processes (see dof_post.h).
#include "post/dof_post.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace ppm {

double max_coc_pixels(const Camera& camera, double near_depth, double far_depth) {
  near_depth = std::fmax(near_depth, std::fmax(camera.clip_start, 1e-9));
  // |1/S - 1/z| is largest at one end of the range (inf at the far end means 1/S).
  const double far_coc = std::isfinite(far_depth) ? camera.coc_pixels(far_depth) : camera.coc_pixels(1e300);
  return std::fmax(camera.coc_pixels(near_depth), far_coc);
}

std::vector<float> dof_post_thin_lens(const std::vector<float>& rgba, const std::vector<float>& depth,
                                      const Camera& camera, int max_radius) {
  const int W = camera.width, H = camera.height;
  std::vector<float> radius(static_cast<size_t>(W) * H);
  float largest = 0.0f;
  for (size_t i = 0; i < radius.size(); ++i) {
    const double z = std::isfinite(depth[i]) ? depth[i] : 1e300;
    radius[i] = static_cast<float>(std::fmin(0.5 * camera.coc_pixels(z), max_radius));
    largest = std::max(largest, radius[i]);
  }
  const int reach = static_cast<int>(std::ceil(largest));
  std::vector<float> out(rgba.size());
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t p = static_cast<size_t>(y) * W + x;
      const float zp = depth[p], rp = radius[p];
      double sum[3] = {0, 0, 0}, weight = 0.0;
      for (int dy = -reach; dy <= reach; ++dy) {
        const int qy = y + dy;
        if (qy < 0 || qy >= H) continue;
        for (int dx = -reach; dx <= reach; ++dx) {
          const int qx = x + dx;
          if (qx < 0 || qx >= W) continue;
          const size_t q = static_cast<size_t>(qy) * W + qx;
          const float rq = std::max(radius[q], 0.5f);
          const float dist = std::sqrt(static_cast<float>(dx * dx + dy * dy));
          // q's disk must reach p (anti-aliased edge) ...
          const float cover = std::clamp(rq - dist + 0.5f, 0.0f, 1.0f);
          if (cover <= 0.0f) continue;
          // ... and q may cover p only from in front of it, unless p is itself
          // blurred at least that far (then p sees around its own occluders).
          if (depth[q] > zp && dist > rp) continue;
          const double w = cover / (rq * rq);
          for (int c = 0; c < 3; ++c) sum[c] += w * rgba[4 * q + c];
          weight += w;
        }
      }
      for (int c = 0; c < 3; ++c) out[4 * p + c] = weight > 0.0 ? static_cast<float>(sum[c] / weight) : rgba[4 * p + c];
      out[4 * p + 3] = rgba[4 * p + 3];
    }
  return out;
}

std::vector<float> dof_post_report_thirds(const std::vector<float>& rgba, const std::vector<float>& depth,
                                          int width, int height) {
  const size_t n = static_cast<size_t>(width) * height;
  std::vector<float> sorted(depth.begin(), depth.end());
  std::sort(sorted.begin(), sorted.end());
  const float third = sorted[n / 3], two_thirds = sorted[2 * n / 3];
  std::vector<float> out(rgba);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t p = static_cast<size_t>(y) * width + x;
      const int k = depth[p] < third ? 2 : (depth[p] < two_thirds ? 1 : 0);  // box half-width
      if (k == 0) continue;
      double sum[3] = {0, 0, 0};
      int count = 0;
      for (int dy = -k; dy <= k; ++dy)
        for (int dx = -k; dx <= k; ++dx) {
          const int qx = std::clamp(x + dx, 0, width - 1), qy = std::clamp(y + dy, 0, height - 1);
          const size_t q = static_cast<size_t>(qy) * width + qx;
          for (int c = 0; c < 3; ++c) sum[c] += rgba[4 * q + c];
          ++count;
        }
      for (int c = 0; c < 3; ++c) out[4 * p + c] = static_cast<float>(sum[c] / count);
    }
  return out;
}

}  // namespace ppm
