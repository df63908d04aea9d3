// A scene's triangle meshes: each add_mesh's vertices (world space, in double, shared by its
// triangles), its triangles in the order they were added (their vertices, material and mesh), and
// what their corners carry (normals, UVs, tangents, an attribute), kept per vertex where the input
// gives them so and per corner otherwise. A triangle costs its three vertex indices, its material
// and mesh, and its share of the vertices, instead of its own copy of three double corners.
#pragma once

#include "base/huge_pages.h"
#include "geometry/triangle.h"
#include "math/types.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace ppm {

// Plain arrays describing one mesh in world space, as the exporter produces them.
struct MeshInput {
  std::string name;
  std::vector<Vec3> positions;
  std::vector<uint32_t> triangles;       // 3 vertex indices per triangle
  std::vector<Vec3> normals;             // empty (flat), one per vertex, or 3 per triangle (corners)
  std::vector<Vec2> uvs;                 // empty, one per vertex, or 3 per triangle (corners)
  std::vector<glm::dvec4> tangents;      // empty or as uvs: the UV map's tangent (xyz), bitangent sign (w)
  std::vector<glm::dvec4> colors;        // empty or as uvs: an attribute node programs read (RGBA)
  std::vector<uint32_t> materials;       // one per triangle, or a single value for all
  uint32_t object_id = 0;
  uint8_t visibility = kAllRayKinds;  // the RayKinds that see it, and kHoldoutFlag for a Holdout object
};

struct TriangleVertices {
  uint32_t v[3];  // indices into MeshStore::vertices
};

// Where one mesh's values of an attribute are: from `first` in its array, one a vertex of the mesh
// (`per_vertex`) or three a triangle, its corners in order; first < 0: the mesh has none.
struct AttributeRange {
  int64_t first = -1;
  bool per_vertex = false;
  bool present() const { return first >= 0; }
  bool same_layout(const AttributeRange& o) const { return present() == o.present() && per_vertex == o.per_vertex; }
};

// One add_mesh: its triangles (contiguous in triangle order) and vertices (contiguous in `vertices`).
struct MeshRecord {
  uint32_t first_triangle = 0, triangle_count = 0, first_vertex = 0, vertex_count = 0, object = 0;
  uint8_t visibility = 0;
  AttributeRange normals, uvs, tangents, colors;
};

struct TriangleInfo {
  uint32_t material, mesh;  // mesh: an index into MeshStore::meshes
};

struct MeshStore {
  HugePageFillVector<Vec3> vertices;  // random rays read them all over (see huge_pages.h)
  // In triangle order. The scene moves them into its BVH leaf records once built (then this is empty).
  std::vector<TriangleVertices> triangles;
  std::vector<TriangleInfo> info;
  std::vector<MeshRecord> meshes;
  std::vector<Vec3f> normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec4> tangents;  // xyz and the bitangent's sign (+-1)
  std::vector<glm::vec4> colors;    // the attribute node programs read (MeshInput::colors)

  // Appends a mesh the scene has checked.
  void append(const MeshInput& mesh);
  // Appends mesh `record` of `from` (whose `triangles` are restored) as it is there.
  void append_copy(const MeshStore& from, const MeshRecord& record);
  // The attribute layouts append would give `mesh` (the ranges' first is 0 where present).
  static MeshRecord layout_of(const MeshInput& mesh);
  // Writes `mesh` over mesh `index`, which has as many triangles and vertices and the same layouts;
  // `triangle_at(t)` is where triangle t's vertex indices live (here, or in the scene's leaves).
  template <class TriangleAt>
  void rewrite(uint32_t index, const MeshInput& mesh, TriangleAt&& triangle_at);

  uint32_t triangle_count() const { return static_cast<uint32_t>(info.size()); }
  TrianglePrim triangle(const TriangleVertices& t) const {
    const Vec3& a = vertices[t.v[0]];
    return TrianglePrim{a, vertices[t.v[1]] - a, vertices[t.v[2]] - a};
  }
  // The value of attribute `range` of `mesh` at corner k (vertex `vertex`) of `triangle`.
  template <class T>
  const T& corner(const std::vector<T>& values, const AttributeRange& range, const MeshRecord& mesh,
                  uint32_t triangle, uint32_t vertex, int k) const {
    return values[static_cast<size_t>(range.first) +
                  (range.per_vertex ? vertex - mesh.first_vertex : 3 * size_t(triangle - mesh.first_triangle) + k)];
  }
  // Its values at the three corners (vertices `v`) of `triangle`.
  template <class T>
  std::array<T, 3> corners(const std::vector<T>& values, const AttributeRange& range, const MeshRecord& mesh,
                           uint32_t triangle, const TriangleVertices& v) const {
    return {corner(values, range, mesh, triangle, v.v[0], 0), corner(values, range, mesh, triangle, v.v[1], 1),
            corner(values, range, mesh, triangle, v.v[2], 2)};
  }
  // Vertex v moves to position[v], each within its own mesh's range (per-vertex attributes with it);
  // `triangles` are the caller's to renumber.
  void reorder_vertices(const std::vector<uint32_t>& position);
  // The indices of object `object`'s meshes, in order.
  const std::vector<uint32_t>& meshes_of(uint32_t object) const;
  size_t memory_bytes() const;
  void shrink_to_fit();  // capacity to size, once a build has made them

 private:
  // meshes_of's index over `meshes` (an instancer moved replaces thousands of objects' meshes), made
  // again after append; rewrite changes no record's object.
  mutable std::unordered_map<uint32_t, std::vector<uint32_t>> by_object_;
  mutable bool by_object_made_ = false;
};

// The normal at a mesh's vertex or corner as stored: normalised, or (where the input's cannot be) the
// triangle's own normal, which a per-vertex layout cannot hold (such meshes keep theirs per corner).
bool normals_fit_per_vertex(const MeshInput& mesh);

template <class TriangleAt>
void MeshStore::rewrite(uint32_t index, const MeshInput& mesh, TriangleAt&& triangle_at) {
  MeshRecord& record = meshes[index];
  record.visibility = mesh.visibility;
  for (uint32_t i = 0; i < record.vertex_count; ++i) vertices[record.first_vertex + i] = mesh.positions[i];
  MeshStore values;  // this mesh's values, made as append makes them, then written over the old ones
  values.append(mesh);
  auto copy = [](auto& to, const AttributeRange& at, const auto& from) {
    if (at.present()) std::copy(from.begin(), from.end(), to.begin() + at.first);
  };
  copy(normals, record.normals, values.normals);
  copy(uvs, record.uvs, values.uvs);
  copy(tangents, record.tangents, values.tangents);
  copy(colors, record.colors, values.colors);
  for (uint32_t t = 0; t < record.triangle_count; ++t) {
    TriangleVertices& out = triangle_at(record.first_triangle + t);
    for (int k = 0; k < 3; ++k) out.v[k] = values.triangles[t].v[k] + record.first_vertex;
    info[record.first_triangle + t].material = values.info[t].material;
  }
}

}  // namespace ppm
