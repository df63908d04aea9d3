// An RGBA float image sampled bilinearly with repeat wrapping, in linear colour.
// Row 0 is the bottom of the image (Blender's convention), so v = 0 is row 0.
#pragma once

#include "math/types.h"

#include <vector>

namespace ppm {

struct Texture {
  int width = 0, height = 0;
  std::vector<float> rgba;  // height * width * 4
  float max_rgb = 0.0f;     // largest colour component (its gain as an albedo)

  Color lookup(const Vec2& uv) const {
    const double x = (uv.x - std::floor(uv.x)) * width - 0.5;
    const double y = (uv.y - std::floor(uv.y)) * height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const int x0 = wrap(static_cast<int>(fx), width), x1 = wrap(x0 + 1, width);
    const int y0 = wrap(static_cast<int>(fy), height), y1 = wrap(y0 + 1, height);
    return (1 - ax) * (1 - ay) * texel(x0, y0) + ax * (1 - ay) * texel(x1, y0) +
           (1 - ax) * ay * texel(x0, y1) + ax * ay * texel(x1, y1);
  }

 private:
  static int wrap(int i, int n) { return ((i % n) + n) % n; }
  Color texel(int x, int y) const {
    const float* p = &rgba[(static_cast<size_t>(y) * width + x) * 4];
    return Color(p[0], p[1], p[2]);
  }
};

}  // namespace ppm
