// Triangle meshes: added to a scene, or replaced in place in a dynamic one (see scene.h).
#include "scene/scene.h"

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
  const MeshLayout layout{per_vertex(mesh.normals.size(), nv, nt, what, "normals"),
                          per_vertex(mesh.uvs.size(), nv, nt, what, "uvs"),
                          per_vertex(mesh.tangents.size(), nv, nt, what, "tangents"),
                          per_vertex(mesh.colors.size(), nv, nt, what, "colors")};
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

}  // namespace

void Scene::add_mesh(MeshInput mesh) {
  ensure_mutable();
  restore_triangles();
  const std::string what = quoted("mesh", mesh.name);
  const MeshLayout layout = check_arrays(mesh, what);
  for (uint32_t m : mesh.materials) check_material(m, what);
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
  invalidate();
}

void Scene::replace_mesh(MeshInput mesh) {
  ensure_mutable();
  const std::string what = quoted("mesh", mesh.name);
  const MeshLayout layout = check_arrays(mesh, what);
  for (uint32_t m : mesh.materials) check_material(m, what);
  const uint32_t first = object_triangles(mesh.object_id, mesh.triangles.size() / 3, what);
  for (size_t t = first; t < first + mesh.triangles.size() / 3; ++t) {
    const TriangleInfo& before = triangle_info_[t];
    if ((before.corners >= 0) != !mesh.normals.empty() || (before.uvs >= 0) != !mesh.uvs.empty() ||
        (before.tangents >= 0) != !mesh.tangents.empty() || (before.colors >= 0) != !mesh.colors.empty())
      fail(what, "has other attributes (normals, uvs, tangents, colors) than the mesh it replaces");
  }
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
    moved_groups_.push_back(object_group_.at(mesh.object_id));
    invalidate_lights();
  } else {
    invalidate();
  }
}

// The first of object `object`'s triangles, checked to be a contiguous range of `count` triangles,
// all of the object. A built dynamic scene finds them through the object's BVH slots, in time
// proportional to the object (an instancer moved replaces each of thousands of instances); other
// scenes scan every triangle.
uint32_t Scene::object_triangles(uint32_t object, size_t count, const std::string& what) const {
  size_t first = 0, found = 0;
  bool contiguous = true;
  if (dynamic_ && geometry_built_) {
    const auto group = object_group_.find(object);
    const uint32_t slot = group == object_group_.end() ? 0 : object_bvh_->first_slot(group->second);
    const uint32_t slots = group == object_group_.end() ? 0 : object_bvh_->slot_count(group->second);
    size_t last = 0;
    for (uint32_t s = slot; s < slot + slots; ++s) {
      if (leaf_prims_[s].kind != PrimitiveKind::Triangle) fail(what, "its object is not a triangle mesh alone");
      first = found == 0 ? leaf_prims_[s].index : std::min<size_t>(first, leaf_prims_[s].index);
      last = std::max<size_t>(last, leaf_prims_[s].index);
      ++found;
    }
    contiguous = found == 0 || last - first + 1 == found;
  } else {
    for (size_t i = 0; i < triangle_info_.size(); ++i) {
      if (triangle_info_[i].object != object) continue;
      if (found == 0) first = i;
      contiguous = contiguous && i == first + found++;
    }
    for (const SphereInfo& s : spheres_)
      if (s.object == object) fail(what, "its object is not a triangle mesh alone");
    for (const RevolveSegment& r : revolve_segments_)
      if (r.object == object) fail(what, "its object is not a triangle mesh alone");
  }
  if (found == 0) fail(what, "object " + std::to_string(object) + " has no mesh in the scene");
  if (!contiguous) fail(what, "its object's triangles were added by more than one add_mesh");
  if (found != count)
    fail(what, "has " + std::to_string(count) + " triangles where its object has " + std::to_string(found));
  return static_cast<uint32_t>(first);
}

}  // namespace ppm
