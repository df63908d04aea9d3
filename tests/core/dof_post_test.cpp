// The report's thirds rule: nearest third of pixels (by depth) box-blurred 5x5,
// middle third 3x3, farthest third untouched.
#include "post/dof_post.h"
#include "math/rng.h"

#include <gtest/gtest.h>

namespace ppm {
namespace {

TEST(DofPost, ReportThirdsBlursNearThirdFiveByFiveAndMiddleThreeByThree) {
  const int W = 30, H = 12;
  Rng rng(1, 2, 3);
  std::vector<float> rgba(W * H * 4), depth(W * H);
  for (auto& v : rgba) v = static_cast<float>(rng.uniform());
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) depth[y * W + x] = static_cast<float>(x < 10 ? 1.0 : (x < 20 ? 2.0 : 3.0)) + 0.001f * y;
  const std::vector<float> out = dof_post_report_thirds(rgba, depth, W, H);
  auto box = [&](int x, int y, int k, int c) {
    double s = 0;
    for (int dy = -k; dy <= k; ++dy)
      for (int dx = -k; dx <= k; ++dx) s += rgba[((y + dy) * W + (x + dx)) * 4 + c];
    return s / ((2 * k + 1) * (2 * k + 1));
  };
  for (int y = 2; y < H - 2; ++y)
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(out[(y * W + 5) * 4 + c], box(5, y, 2, c), 1e-5);    // near third: 5x5
      EXPECT_NEAR(out[(y * W + 15) * 4 + c], box(15, y, 1, c), 1e-5);  // middle third: 3x3
      EXPECT_EQ(out[(y * W + 25) * 4 + c], rgba[(y * W + 25) * 4 + c]);  // far third: sharp
    }
}

TEST(DofPost, ThinLensLeavesInFocusImageUntouched) {
  Camera cam;
  cam.width = 16;
  cam.height = 8;
  cam.focus_distance = 3.0;
  cam.aperture_radius = 0.05;
  Rng rng(4, 5, 6);
  std::vector<float> rgba(16 * 8 * 4), depth(16 * 8, 3.0f);
  for (auto& v : rgba) v = static_cast<float>(rng.uniform());
  const std::vector<float> out = dof_post_thin_lens(rgba, depth, cam, 32);
  for (size_t i = 0; i < rgba.size(); ++i) EXPECT_FLOAT_EQ(out[i], rgba[i]);
}

}  // namespace
}  // namespace ppm
