// Shared by the BVH tests: the boxes of a triangle soup, as the scene builds them.
#pragma once

#include "geometry/triangle.h"
#include "math/aabb.h"

#include <vector>

namespace ppm {

inline std::vector<Aabb> triangle_boxes(const std::vector<TrianglePrim>& tris) {
  std::vector<Aabb> boxes;
  boxes.reserve(tris.size());
  for (const auto& t : tris) {
    Aabb b;
    b.grow(t.v0);
    b.grow(t.v0 + t.e1);
    b.grow(t.v0 + t.e2);
    boxes.push_back(b);
  }
  return boxes;
}

}  // namespace ppm
