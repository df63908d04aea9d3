// Depth of field as a post-process on the finished image and its per-pixel
// depth (view-axis distance of the first hit, inf for none).
//   thin lens:   each pixel spreads over its circle of confusion (thin-lens
//                equation, the camera's focus distance and aperture); gathered
//                with a depth test so a sharp foreground is not smeared by the
//                blurred background behind it, while a blurred foreground
//                spreads over what is behind it.
//   report thirds: the 2019 report's rule: sort pixels by depth, box-blur the
//                nearest third 5x5 and the middle third 3x3 (focal plane at the far third).
#pragma once

#include "geometry/camera.h"

#include <vector>

namespace ppm {

// rgba and depth are top row first, W*H*4 and W*H. Returns the blurred rgba.
std::vector<float> dof_post_thin_lens(const std::vector<float>& rgba, const std::vector<float>& depth,
                                      const Camera& camera, int max_radius);
std::vector<float> dof_post_report_thirds(const std::vector<float>& rgba, const std::vector<float>& depth,
                                          int width, int height);

// Largest circle of confusion (pixels) over a depth range; used to skip DoF
// work when it stays under a pixel.
double max_coc_pixels(const Camera& camera, double near_depth, double far_depth);

}  // namespace ppm
