// A closed mesh's volume and its open edges (see mesh_volume.h).
#include "geometry/mesh_volume.h"

#include <algorithm>
#include <array>

namespace ppm {

double signed_volume(const std::vector<TriangleCorners>& triangles) {
  if (triangles.empty()) return 0.0;
  const Vec3 c = triangles.front()[0];
  double six_v = 0.0;
  for (const TriangleCorners& t : triangles) six_v += glm::dot(t[0] - c, glm::cross(t[1] - t[0], t[2] - t[0]));
  return six_v / 6.0;
}

namespace {

using Corner = std::array<double, 3>;
using Edge = std::pair<Corner, Corner>;  // its corners in lexicographic order

Edge edge(const Vec3& a, const Vec3& b) {
  const Corner ca{a.x, a.y, a.z}, cb{b.x, b.y, b.z};
  return ca < cb ? Edge{ca, cb} : Edge{cb, ca};
}

}  // namespace

size_t open_edges(const std::vector<TriangleCorners>& triangles) {
  std::vector<Edge> edges;
  edges.reserve(3 * triangles.size());
  for (const TriangleCorners& t : triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] != t[(k + 1) % 3]) edges.push_back(edge(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());  // a hash would do; sorting needs no hash of doubles
  size_t open = 0;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    open += (j - i) % 2;
    i = j;
  }
  return open;
}

}  // namespace ppm
