// A closed mesh's volume by the divergence theorem and its open edges (geometry/mesh_volume.h), on
// a non-convex L-shaped prism whose volume is known: 3 * height.
#include "geometry/mesh_volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace ppm {
namespace {

// The L of area 3 in the xy plane, counter-clockwise; corner 3 (1, 1) is the reflex one, and a fan
// from it covers the L with four counter-clockwise triangles.
const std::vector<Vec2> kL = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};

// The L extruded from z = 0 to `height` and moved by `offset`: 20 triangles facing outward.
std::vector<TriangleCorners> l_prism(double height, const Vec3& offset = Vec3(0.0)) {
  auto at = [&](int i, double z) { return Vec3(kL[i % 6].x, kL[i % 6].y, z) + offset; };
  std::vector<TriangleCorners> t;
  for (int k : {4, 5, 0, 1}) {  // the fan from corner 3: top counter-clockwise, bottom turned over
    t.push_back({at(3, height), at(k, height), at(k + 1, height)});
    t.push_back({at(3, 0.0), at(k + 1, 0.0), at(k, 0.0)});
  }
  for (int i = 0; i < 6; ++i) {  // each side a quad, outward for a counter-clockwise outline
    t.push_back({at(i, 0.0), at(i + 1, 0.0), at(i + 1, height)});
    t.push_back({at(i, 0.0), at(i + 1, height), at(i, height)});
  }
  return t;
}

TEST(MeshVolume, LPrismVolumeIsItsAreaTimesHeight) {
  EXPECT_NEAR(signed_volume(l_prism(0.7)), 2.1, 1e-14);
  EXPECT_EQ(open_edges(l_prism(0.7)), 0u);
}

TEST(MeshVolume, InwardFacingIsNegative) {
  std::vector<TriangleCorners> t = l_prism(1.5);
  for (TriangleCorners& c : t) std::swap(c[1], c[2]);
  EXPECT_NEAR(signed_volume(t), -4.5, 1e-14);
}

TEST(MeshVolume, FarFromTheOriginKeepsItsDigits) {
  // From the origin, each tetrahedron would be ~1e18 and their sum lose every digit of 4.5.
  EXPECT_NEAR(signed_volume(l_prism(1.5, Vec3(1e6, -2e6, 3e6))), 4.5, 1e-9);
}

TEST(MeshVolume, OpenMeshHasOddEdges) {
  std::vector<TriangleCorners> t = l_prism(1.0);
  t.pop_back();  // a side quad's half gone: its three edges are each left with one triangle
  EXPECT_EQ(open_edges(t), 3u);
  t.clear();
  EXPECT_EQ(open_edges(t), 0u);
  EXPECT_EQ(signed_volume(t), 0.0);
}

TEST(MeshVolume, DegenerateTrianglesAndDoubleSidedSheetsEncloseNothing) {
  std::vector<TriangleCorners> t = l_prism(1.0);
  t.push_back({Vec3(0.0), Vec3(0.0), Vec3(2, 0, 0)});  // a sliver on an existing edge: no length to add
  t.push_back({Vec3(0.0), Vec3(2, 0, 0), Vec3(2, 0, 0)});
  EXPECT_EQ(open_edges(t), 0u);
  EXPECT_NEAR(signed_volume(t), 3.0, 1e-14);
  // A quad and its back: closed by the edge count, and no volume (prepare_medium_lights skips it).
  const std::vector<TriangleCorners> sheet = {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)},
                                              {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0)}};
  EXPECT_EQ(open_edges(sheet), 0u);
  EXPECT_EQ(signed_volume(sheet), 0.0);
}

}  // namespace
}  // namespace ppm
