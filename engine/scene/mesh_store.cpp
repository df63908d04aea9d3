// A scene's triangle meshes (see mesh_store.h).
#include "scene/mesh_store.h"

#include "base/parallel.h"
#include "scene/input_checks.h"

#include <type_traits>

namespace ppm {
using scene_input::safe_normalize;

namespace {

// Is the attribute given one per vertex (else one per corner, or not at all)? Per vertex where both
// fit (a lone triangle), as the scene's checks read it.
bool given_per_vertex(size_t given, const MeshInput& mesh) {
  const size_t vertices = mesh.positions.size(), triangles = mesh.triangles.size() / 3;
  return given == vertices && vertices != 3 * triangles;
}

AttributeRange range_of(size_t given, bool per_vertex) {
  AttributeRange r;
  r.first = given == 0 ? -1 : 0;
  r.per_vertex = given != 0 && per_vertex;
  return r;
}

glm::vec4 tangent_of(const glm::dvec4& t) { return glm::vec4(t.x, t.y, t.z, t.w < 0.0 ? -1.0f : 1.0f); }

// Appends an attribute's stored values for `mesh`: one a vertex, or one a corner (from the input's per
// vertex or per corner values). `convert` turns an input value into the stored one.
template <class T, class U, class Convert>
void append_values(std::vector<T>& out, AttributeRange& range, const std::vector<U>& given, const MeshInput& mesh,
                   Convert&& convert) {
  if (!range.present()) return;
  range.first = static_cast<int64_t>(out.size());
  if (range.per_vertex) {
    for (const U& value : given) out.push_back(convert(value));
    return;
  }
  const bool from_vertices = given_per_vertex(given.size(), mesh);
  for (size_t t = 0; t < mesh.triangles.size() / 3; ++t)
    for (int k = 0; k < 3; ++k) out.push_back(convert(from_vertices ? given[mesh.triangles[3 * t + k]] : given[3 * t + k]));
}

template <class T>
void append_copied(std::vector<T>& out, AttributeRange& range, const std::vector<T>& from,
                   const AttributeRange& from_range, size_t count) {
  if (!from_range.present()) return;
  range.first = static_cast<int64_t>(out.size());
  out.insert(out.end(), from.begin() + from_range.first, from.begin() + from_range.first + count);
}

template <class V>
size_t bytes(const V& v) {
  return v.capacity() * sizeof(v[0]);
}

template <class V>
void shrink(V& v) {
  if (v.capacity() - v.size() > v.capacity() / 8) v.shrink_to_fit();
}

}  // namespace

bool normals_fit_per_vertex(const MeshInput& mesh) {
  Vec3 unit;
  for (const Vec3& n : mesh.normals)
    if (!safe_normalize(n, unit)) return false;
  return true;
}

MeshRecord MeshStore::layout_of(const MeshInput& mesh) {
  MeshRecord r;
  r.normals = range_of(mesh.normals.size(), given_per_vertex(mesh.normals.size(), mesh) && normals_fit_per_vertex(mesh));
  r.uvs = range_of(mesh.uvs.size(), given_per_vertex(mesh.uvs.size(), mesh));
  r.tangents = range_of(mesh.tangents.size(), given_per_vertex(mesh.tangents.size(), mesh));
  r.colors = range_of(mesh.colors.size(), given_per_vertex(mesh.colors.size(), mesh));
  return r;
}

void MeshStore::append(const MeshInput& mesh) {
  const size_t nt = mesh.triangles.size() / 3;
  MeshRecord r = layout_of(mesh);
  r.first_triangle = triangle_count();
  r.triangle_count = static_cast<uint32_t>(nt);
  r.first_vertex = static_cast<uint32_t>(vertices.size());
  r.vertex_count = static_cast<uint32_t>(mesh.positions.size());
  r.object = mesh.object_id;
  r.visibility = mesh.visibility;
  const uint32_t index = static_cast<uint32_t>(meshes.size());
  vertices.insert(vertices.end(), mesh.positions.begin(), mesh.positions.end());
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t* idx = &mesh.triangles[3 * t];
    triangles.push_back(TriangleVertices{{r.first_vertex + idx[0], r.first_vertex + idx[1], r.first_vertex + idx[2]}});
    info.push_back(TriangleInfo{mesh.materials.size() == 1 ? mesh.materials[0] : mesh.materials[t], index});
  }
  if (r.normals.present() && !r.normals.per_vertex) {  // per corner: a corner's own, or its triangle's
    r.normals.first = static_cast<int64_t>(normals.size());
    const bool from_vertices = given_per_vertex(mesh.normals.size(), mesh);
    for (size_t t = 0; t < nt; ++t) {
      const TrianglePrim tri = triangle(triangles[r.first_triangle + t]);
      for (int k = 0; k < 3; ++k) {
        Vec3 n;
        if (!safe_normalize(from_vertices ? mesh.normals[mesh.triangles[3 * t + k]] : mesh.normals[3 * t + k], n))
          n = triangle_normal(tri);
        normals.push_back(Vec3f(n));
      }
    }
  } else {
    append_values(normals, r.normals, mesh.normals, mesh, [](const Vec3& n) {
      Vec3 unit(0.0);
      safe_normalize(n, unit);  // (normals_fit_per_vertex: it can)
      return Vec3f(unit);
    });
  }
  append_values(uvs, r.uvs, mesh.uvs, mesh, [](const Vec2& uv) { return glm::vec2(uv); });
  append_values(tangents, r.tangents, mesh.tangents, mesh, tangent_of);
  append_values(colors, r.colors, mesh.colors, mesh, [](const glm::dvec4& c) { return glm::vec4(c); });
  meshes.push_back(r);
  by_object_made_ = false;
}

void MeshStore::append_copy(const MeshStore& from, const MeshRecord& record) {
  MeshRecord r = record;
  const uint32_t index = static_cast<uint32_t>(meshes.size());
  r.first_triangle = triangle_count();
  r.first_vertex = static_cast<uint32_t>(vertices.size());
  vertices.insert(vertices.end(), from.vertices.begin() + record.first_vertex,
                  from.vertices.begin() + record.first_vertex + record.vertex_count);
  for (uint32_t t = record.first_triangle; t < record.first_triangle + record.triangle_count; ++t) {
    TriangleVertices tv = from.triangles[t];
    for (uint32_t& v : tv.v) v = v - record.first_vertex + r.first_vertex;
    triangles.push_back(tv);
    info.push_back(TriangleInfo{from.info[t].material, index});
  }
  auto count = [&](const AttributeRange& a) { return a.per_vertex ? size_t(record.vertex_count) : 3 * size_t(record.triangle_count); };
  append_copied(normals, r.normals, from.normals, record.normals, count(record.normals));
  append_copied(uvs, r.uvs, from.uvs, record.uvs, count(record.uvs));
  append_copied(tangents, r.tangents, from.tangents, record.tangents, count(record.tangents));
  append_copied(colors, r.colors, from.colors, record.colors, count(record.colors));
  meshes.push_back(r);
  by_object_made_ = false;
}

void MeshStore::reorder_vertices(const std::vector<uint32_t>& position) {
  HugePageFillVector<Vec3> moved(vertices.size());  // unwritten: the loop's page faults on every thread
  parallel_for(hardware_threads(), vertices.size(), [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) moved[position[v]] = vertices[v];
  });
  vertices.swap(moved);
  auto reorder = [&](auto& values, const AttributeRange& range, const MeshRecord& mesh) {
    if (!range.per_vertex) return;
    auto* first = &values[static_cast<size_t>(range.first)];
    std::vector<std::decay_t<decltype(*first)>> old(first, first + mesh.vertex_count);
    for (uint32_t i = 0; i < mesh.vertex_count; ++i) first[position[mesh.first_vertex + i] - mesh.first_vertex] = old[i];
  };
  for (const MeshRecord& mesh : meshes) {
    reorder(normals, mesh.normals, mesh);
    reorder(uvs, mesh.uvs, mesh);
    reorder(tangents, mesh.tangents, mesh);
    reorder(colors, mesh.colors, mesh);
  }
}

const std::vector<uint32_t>& MeshStore::meshes_of(uint32_t object) const {
  static const std::vector<uint32_t> kNone;
  if (!by_object_made_) {
    by_object_.clear();
    for (uint32_t i = 0; i < meshes.size(); ++i) by_object_[meshes[i].object].push_back(i);
    by_object_made_ = true;
  }
  const auto found = by_object_.find(object);
  return found == by_object_.end() ? kNone : found->second;
}

size_t MeshStore::memory_bytes() const {
  return bytes(vertices) + bytes(triangles) + bytes(info) + bytes(meshes) + bytes(normals) + bytes(uvs) +
         bytes(tangents) + bytes(colors);
}

void MeshStore::shrink_to_fit() {
  shrink(vertices);
  shrink(info);
  shrink(meshes);
  shrink(normals);
  shrink(uvs);
  shrink(tangents);
  shrink(colors);
}

}  // namespace ppm
