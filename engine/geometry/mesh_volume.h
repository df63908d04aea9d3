// What a closed triangle mesh encloses: its volume by the divergence theorem and whether it is
// closed at all. Used for the regions of emitting media (scene/medium_regions.cpp), whose power is
// 4 pi L_e V.
//
// The divergence theorem turns the volume into a sum over the surface: V = sum over triangles of
// the signed tetrahedron (v0 - c) . (e1 x e2) / 6 from any point c. It is exact for a closed mesh
// (to rounding), positive for outward-facing triangles, the same from every c, and costs one pass
// over the triangles. Rejection sampling's acceptance ratio would give V too, but only as an
// estimate with noise, and the power of a light must be known before its photons are drawn.
// For an open mesh the sum depends on c and the enclosed volume is not defined: open_edges tells.
#pragma once

#include "math/types.h"

#include <array>
#include <cstddef>
#include <vector>

namespace ppm {

// A triangle by its corners as the mesh stores them (not v0 + e1: that sum rounds differently in
// the triangles that share a corner, and their edges would no longer match).
using TriangleCorners = std::array<Vec3, 3>;

// The signed volume the triangles enclose (outward normals: positive), from their first corner
// (near the mesh, so that the products keep their digits for a mesh far from the origin).
double signed_volume(const std::vector<TriangleCorners>& triangles);

// Edges (by their corners' exact positions, either direction) that an odd number of triangles
// share: 0 for a closed mesh, including one whose vertices are split at seams. Edges of no length
// (a degenerate triangle's) are left out; its other two then coincide and pair up.
size_t open_edges(const std::vector<TriangleCorners>& triangles);

}  // namespace ppm
