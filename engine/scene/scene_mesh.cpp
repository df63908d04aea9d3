// Triangle meshes: added to a scene, or replaced in place in a dynamic one (see scene.h).
#include "scene/scene.h"

#include "geometry/bezier_revolve.h"
#include "geometry/object_bvh.h"
#include "scene/input_checks.h"

#include <algorithm>
#include <cmath>

namespace ppm {
using namespace scene_input;

namespace {

// Which of a mesh's attribute arrays are per vertex (the others are per triangle corner or empty).
struct MeshLayout {
  bool normals, uvs, tangents, colors;
};

// One per vertex, one per corner, or none; per vertex where both fit (a lone triangle).
bool per_vertex(size_t given, size_t vertices, size_t triangles, const std::string& what, const char* field) {
  if (given != 0 && given != vertices && given != 3 * triangles)
    fail(what, std::string(field) + " must be given per vertex or per triangle corner");
  return given == vertices && vertices != 3 * triangles;
}

bool finite4(const glm::dvec4& v, double limit) {
  return std::fabs(v.x) < limit && std::fabs(v.y) < limit && std::fabs(v.z) < limit && std::fabs(v.w) < limit;
}

MeshLayout mesh_layout(const MeshInput& mesh, const std::string& what) {
  const size_t nv = mesh.positions.size(), nt = mesh.triangles.size() / 3;
  return MeshLayout{per_vertex(mesh.normals.size(), nv, nt, what, "normals"), per_vertex(mesh.uvs.size(), nv, nt, what, "uvs"),
                    per_vertex(mesh.tangents.size(), nv, nt, what, "tangents"),
                    per_vertex(mesh.colors.size(), nv, nt, what, "colors")};
}

MeshLayout check_arrays(const MeshInput& mesh, const std::string& what) {
  const size_t nv = mesh.positions.size(), nt = mesh.triangles.size() / 3;
  if (nt == 0 || mesh.triangles.size() % 3 != 0) fail(what, "has no triangles");
  for (size_t i = 0; i < nv; ++i) {
    if (!is_finite(mesh.positions[i])) fail(what, "position " + std::to_string(i) + " is not finite");
    check_coordinates(mesh.positions[i], what, "position " + std::to_string(i));
  }
  for (size_t i = 0; i < mesh.triangles.size(); ++i)
    if (mesh.triangles[i] >= nv)
      fail(what, "triangle " + std::to_string(i / 3) + " uses vertex " + std::to_string(mesh.triangles[i]) +
                     " but the mesh has " + std::to_string(nv) + " vertices");
  const MeshLayout layout = mesh_layout(mesh, what);
  for (const glm::dvec4& t : mesh.tangents)
    if (!finite4(t, kInf)) fail(what, "tangents contain NaN or Inf");
  for (const glm::dvec4& c : mesh.colors)
    if (!finite4(c, 1e30)) fail(what, "colors contain NaN, Inf or values beyond 1e30");
  if (mesh.materials.size() != 1 && mesh.materials.size() != nt)
    fail(what, "materials must be one index or one per triangle");
  for (const Vec3& n : mesh.normals)
    if (!is_finite(n)) fail(what, "normals contain NaN or Inf");
  for (const Vec2& uv : mesh.uvs)
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) fail(what, "uvs contain NaN or Inf");
  return layout;
}

// Triangle t of a mesh and what its corners carry, as the scene stores them.
struct MeshTriangle {
  TrianglePrim tri;
  uint32_t material;
  Vec3f normals[3];
  glm::vec2 uvs[3];
  glm::vec4 tangents[3], colors[3];
};

MeshTriangle mesh_triangle(const MeshInput& mesh, const MeshLayout& layout, size_t t) {
  const uint32_t* idx = &mesh.triangles[3 * t];
  const Vec3 &a = mesh.positions[idx[0]], &b = mesh.positions[idx[1]], &c = mesh.positions[idx[2]];
  MeshTriangle out;
  out.tri = TrianglePrim{a, b - a, c - a};
  out.material = mesh.materials.size() == 1 ? mesh.materials[0] : mesh.materials[t];
  for (int k = 0; k < 3; ++k) {
    if (!mesh.normals.empty()) {
      Vec3 n;
      if (!safe_normalize(layout.normals ? mesh.normals[idx[k]] : mesh.normals[3 * t + k], n))
        n = triangle_normal(out.tri);
      out.normals[k] = Vec3f(n);
    }
    if (!mesh.uvs.empty()) out.uvs[k] = glm::vec2(layout.uvs ? mesh.uvs[idx[k]] : mesh.uvs[3 * t + k]);
    if (!mesh.tangents.empty()) {
      const glm::dvec4 tangent = layout.tangents ? mesh.tangents[idx[k]] : mesh.tangents[3 * t + k];
      out.tangents[k] = glm::vec4(tangent.x, tangent.y, tangent.z, tangent.w < 0.0 ? -1.0f : 1.0f);
    }
    if (!mesh.colors.empty()) out.colors[k] = glm::vec4(layout.colors ? mesh.colors[idx[k]] : mesh.colors[3 * t + k]);
  }
  return out;
}

// Appends a triangle's three corner values; returns the index of the first (-1: the mesh has none).
template <class T, class U>
int32_t append_corners(std::vector<T>& corners, const U (&values)[3], bool present) {
  if (!present) return -1;
  const int32_t first = static_cast<int32_t>(corners.size());
  for (const U& v : values) corners.push_back(T(v));
  return first;
}

template <class T, class U>
void write_corners(std::vector<T>& corners, int32_t first, const U (&values)[3]) {
  if (first >= 0)
    for (int k = 0; k < 3; ++k) corners[size_t(first) + k] = T(values[k]);
}

// Copies a kept triangle's three corner values into the compacted array; returns their new index.
template <class T>
int32_t keep_corners(const std::vector<T>& from, int32_t first, std::vector<T>& to) {
  if (first < 0) return -1;
  const int32_t index = static_cast<int32_t>(to.size());
  to.insert(to.end(), from.begin() + first, from.begin() + first + 3);
  return index;
}

}  // namespace

void Scene::add_mesh(MeshInput mesh) {
  ensure_mutable();
  const std::string what = quoted("mesh", mesh.name);
  check_arrays(mesh, what);
  for (uint32_t m : mesh.materials) check_material(m, what);
  restore_triangles();
  append_triangles(mesh);
  geometry_changed(mesh.object_id);
}

// Appends a checked mesh's triangles and what their corners carry.
void Scene::append_triangles(const MeshInput& mesh) {
  const MeshLayout layout = mesh_layout(mesh, mesh.name);
  for (size_t t = 0; t < mesh.triangles.size() / 3; ++t) {
    const MeshTriangle m = mesh_triangle(mesh, layout, t);
    triangles_.push_back(m.tri);
    triangle_info_.push_back(TriangleInfo{m.material, mesh.object_id,
                                          append_corners(corner_normals_, m.normals, !mesh.normals.empty()),
                                          append_corners(corner_uvs_, m.uvs, !mesh.uvs.empty()),
                                          append_corners(corner_tangents_, m.tangents, !mesh.tangents.empty()),
                                          append_corners(corner_colors_, m.colors, !mesh.colors.empty()),
                                          mesh.visibility});
  }
}

void Scene::replace_mesh(MeshInput mesh) {
  ensure_mutable();
  const std::string what = quoted("mesh", mesh.name);
  check_arrays(mesh, what);
  for (uint32_t m : mesh.materials) check_material(m, what);
  const ObjectTriangles own = object_triangles(mesh.object_id, what);
  if (own.contiguous && own.count == mesh.triangles.size() / 3 && same_attributes(own.first, mesh))
    rewrite_triangles(mesh, own.first);
  else
    splice_triangles(mesh, own.first);
}

// Do the object's triangles from `first` on carry what the mesh's would (normals, uvs, tangents, colors)?
bool Scene::same_attributes(size_t first, const MeshInput& mesh) const {
  for (size_t t = first; t < first + mesh.triangles.size() / 3; ++t) {
    const TriangleInfo& before = triangle_info_[t];
    if ((before.corners >= 0) != !mesh.normals.empty() || (before.uvs >= 0) != !mesh.uvs.empty() ||
        (before.tangents >= 0) != !mesh.tangents.empty() || (before.colors >= 0) != !mesh.colors.empty())
      return false;
  }
  return true;
}

// The object's triangles from `first` on, as many as the mesh's and with the same attributes, take its
// values in place: in a built dynamic scene build() then refits the object's subtree.
void Scene::rewrite_triangles(const MeshInput& mesh, size_t first) {
  const MeshLayout layout = mesh_layout(mesh, mesh.name);
  const bool in_leaves = triangles_.size() != triangle_info_.size();  // built: see release_triangles
  for (size_t t = 0; t < mesh.triangles.size() / 3; ++t) {
    const MeshTriangle m = mesh_triangle(mesh, layout, t);
    TriangleInfo& info = triangle_info_[first + t];
    info.material = m.material;
    info.visibility = mesh.visibility;
    write_corners(corner_normals_, info.corners, m.normals);
    write_corners(corner_uvs_, info.uvs, m.uvs);
    write_corners(corner_tangents_, info.tangents, m.tangents);
    write_corners(corner_colors_, info.colors, m.colors);
    if (!in_leaves) {
      triangles_[first + t] = m.tri;
      continue;
    }
    LeafPrim& leaf = leaf_prims_[slot_of_triangle_[first + t]];
    leaf.tri = m.tri;
    leaf.visibility = mesh.visibility;
  }
  if (in_leaves && geometry_built_ && dynamic_) {
    moved_objects_.push_back(mesh.object_id);
    invalidate_lights();
  } else {
    geometry_changed(mesh.object_id);
  }
}

// The object's triangles, wherever they are, give way to the mesh's, which take the place of its first:
// the triangle order stays that of a scene built with the mesh there.
void Scene::splice_triangles(const MeshInput& mesh, size_t first) {
  restore_triangles();
  remove_triangles_of(mesh.object_id, mesh.triangles.size() / 3);
  const size_t end = triangles_.size();
  append_triangles(mesh);
  const auto at = static_cast<std::ptrdiff_t>(first), old_end = static_cast<std::ptrdiff_t>(end);
  std::rotate(triangles_.begin() + at, triangles_.begin() + old_end, triangles_.end());
  std::rotate(triangle_info_.begin() + at, triangle_info_.begin() + old_end, triangle_info_.end());
  geometry_changed(mesh.object_id);
}

// Drops the object's triangles and their corners from the triangle-ordered arrays (restored), the
// arrays made anew at their new size, with room for `room` triangles more; returns how many went.
size_t Scene::remove_triangles_of(uint32_t object, size_t room) {
  size_t removed = 0, normals = 0, uvs = 0, tangents = 0, colors = 0;
  for (const TriangleInfo& t : triangle_info_) {
    if (t.object == object) ++removed;
    normals += t.object != object && t.corners >= 0;
    uvs += t.object != object && t.uvs >= 0;
    tangents += t.object != object && t.tangents >= 0;
    colors += t.object != object && t.colors >= 0;
  }
  const size_t kept = triangle_info_.size() - removed;
  std::vector<TrianglePrim> triangles;
  std::vector<TriangleInfo> info;
  std::vector<Vec3f> corner_normals;
  std::vector<glm::vec2> corner_uvs;
  std::vector<glm::vec4> corner_tangents, corner_colors;
  triangles.reserve(kept + room);
  info.reserve(kept + room);
  corner_normals.reserve(3 * (normals + room));
  corner_uvs.reserve(3 * (uvs + room));
  corner_tangents.reserve(3 * (tangents + room));
  corner_colors.reserve(3 * (colors + room));
  for (size_t i = 0; i < triangle_info_.size(); ++i) {
    TriangleInfo t = triangle_info_[i];
    if (t.object == object) continue;
    t.corners = keep_corners(corner_normals_, t.corners, corner_normals);
    t.uvs = keep_corners(corner_uvs_, t.uvs, corner_uvs);
    t.tangents = keep_corners(corner_tangents_, t.tangents, corner_tangents);
    t.colors = keep_corners(corner_colors_, t.colors, corner_colors);
    triangles.push_back(triangles_[i]);
    info.push_back(t);
  }
  triangles_.swap(triangles);
  triangle_info_.swap(info);
  corner_normals_.swap(corner_normals);
  corner_uvs_.swap(corner_uvs);
  corner_tangents_.swap(corner_tangents);
  corner_colors_.swap(corner_colors);
  return removed;
}

size_t Scene::remove_object(uint32_t object) {
  ensure_mutable();
  size_t removed = 0;
  if (std::any_of(triangle_info_.begin(), triangle_info_.end(), [&](const TriangleInfo& t) { return t.object == object; })) {
    restore_triangles();
    removed += remove_triangles_of(object, 0);
  }
  const size_t spheres = spheres_.size(), segments = revolve_segments_.size();
  spheres_.erase(std::remove_if(spheres_.begin(), spheres_.end(), [&](const SphereInfo& s) { return s.object == object; }),
                 spheres_.end());
  revolve_segments_.erase(std::remove_if(revolve_segments_.begin(), revolve_segments_.end(),
                                         [&](const RevolveSegment& r) { return r.object == object; }),
                          revolve_segments_.end());
  removed += spheres - spheres_.size() + segments - revolve_segments_.size();
  if (segments != revolve_segments_.size()) drop_unused_revolves();
  if (removed > 0) geometry_changed(object);
  return removed;
}

// The revolves no segment refers to any more go; the segments' indices follow.
void Scene::drop_unused_revolves() {
  std::vector<int64_t> index(revolves_.size(), -1);
  for (const RevolveSegment& r : revolve_segments_) index[r.revolve] = 0;
  size_t kept = 0;
  for (size_t i = 0; i < revolves_.size(); ++i) {
    if (index[i] < 0) continue;
    index[i] = static_cast<int64_t>(kept);
    revolves_[kept++] = std::move(revolves_[i]);
  }
  revolves_.resize(kept);
  for (RevolveSegment& r : revolve_segments_) r.revolve = static_cast<uint32_t>(index[r.revolve]);
}

// Object `object`'s primitives were added, removed or replaced: a built dynamic scene builds its subtree
// again at the next build() and keeps the other objects'; any other scene builds its BVH afresh.
void Scene::geometry_changed(uint32_t object) {
  if (dynamic_ && geometry_built_) {
    changed_objects_.push_back(object);
    invalidate_lights();
  } else {
    invalidate();
  }
}

// Where object `object`'s triangles are, refused where it has none or primitives of other kinds too. A
// built dynamic scene finds them through the object's BVH slots, in time proportional to the object (an
// instancer moved replaces each of thousands of instances); other scenes scan every triangle.
Scene::ObjectTriangles Scene::object_triangles(uint32_t object, const std::string& what) const {
  ObjectTriangles own;
  if (dynamic_ && geometry_built_ && changed_objects_.empty()) {
    const auto group = object_group_.find(object);
    const uint32_t slot = group == object_group_.end() ? 0 : object_bvh_->first_slot(group->second);
    const uint32_t slots = group == object_group_.end() ? 0 : object_bvh_->slot_count(group->second);
    size_t last = 0;
    for (uint32_t s = slot; s < slot + slots; ++s) {
      if (leaf_prims_[s].kind != PrimitiveKind::Triangle) fail(what, "its object is not a triangle mesh alone");
      own.first = own.count == 0 ? leaf_prims_[s].index : std::min<size_t>(own.first, leaf_prims_[s].index);
      last = std::max<size_t>(last, leaf_prims_[s].index);
      ++own.count;
    }
    own.contiguous = own.count == 0 || last - own.first + 1 == own.count;
  } else {
    for (size_t i = 0; i < triangle_info_.size(); ++i) {
      if (triangle_info_[i].object != object) continue;
      if (own.count == 0) own.first = i;
      own.contiguous = own.contiguous && i == own.first + own.count++;
    }
    for (const SphereInfo& s : spheres_)
      if (s.object == object) fail(what, "its object is not a triangle mesh alone");
    for (const RevolveSegment& r : revolve_segments_)
      if (r.object == object) fail(what, "its object is not a triangle mesh alone");
  }
  if (own.count == 0) fail(what, "object " + std::to_string(object) + " has no mesh in the scene");
  return own;
}

}  // namespace ppm
