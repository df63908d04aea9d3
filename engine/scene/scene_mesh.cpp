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

// One per vertex, one per corner, or none.
void check_count(size_t given, size_t vertices, size_t triangles, const std::string& what, const char* field) {
  if (given != 0 && given != vertices && given != 3 * triangles)
    fail(what, std::string(field) + " must be given per vertex or per triangle corner");
}

bool finite4(const glm::dvec4& v, double limit) {
  return std::fabs(v.x) < limit && std::fabs(v.y) < limit && std::fabs(v.z) < limit && std::fabs(v.w) < limit;
}

void check_arrays(const MeshInput& mesh, const std::string& what) {
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
  check_count(mesh.normals.size(), nv, nt, what, "normals");
  check_count(mesh.uvs.size(), nv, nt, what, "uvs");
  check_count(mesh.tangents.size(), nv, nt, what, "tangents");
  check_count(mesh.colors.size(), nv, nt, what, "colors");
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
}

// Vertex and triangle indices are 32 bits.
void check_room(const MeshStore& meshes, const MeshInput& mesh, const std::string& what) {
  constexpr size_t kMost = (size_t(1) << 32) - 1;
  if (meshes.vertices.size() + mesh.positions.size() > kMost || meshes.info.size() + mesh.triangles.size() / 3 > kMost)
    fail(what, "the scene would hold more than 2^32 - 1 vertices or triangles");
}

// Would `mesh` fit in place of `record`: as many triangles and vertices, the same attribute layouts?
bool fits(const MeshRecord& record, const MeshInput& mesh) {
  const MeshRecord layout = MeshStore::layout_of(mesh);
  return record.triangle_count == mesh.triangles.size() / 3 && record.vertex_count == mesh.positions.size() &&
         record.normals.same_layout(layout.normals) && record.uvs.same_layout(layout.uvs) &&
         record.tangents.same_layout(layout.tangents) && record.colors.same_layout(layout.colors);
}

}  // namespace

void Scene::add_mesh(MeshInput mesh) {
  ensure_mutable();
  const std::string what = quoted("mesh", mesh.name);
  check_arrays(mesh, what);
  check_room(meshes_, mesh, what);
  for (uint32_t m : mesh.materials) check_material(m, what);
  restore_triangles();
  meshes_.append(mesh);
  geometry_changed(mesh.object_id);
}

void Scene::replace_mesh(MeshInput mesh) {
  ensure_mutable();
  const std::string what = quoted("mesh", mesh.name);
  check_arrays(mesh, what);
  check_room(meshes_, mesh, what);
  for (uint32_t m : mesh.materials) check_material(m, what);
  const std::vector<uint32_t> own = object_meshes(mesh.object_id, what);
  if (own.size() == 1 && fits(meshes_.meshes[own[0]], mesh))
    rewrite_mesh(own[0], mesh);
  else
    rebuild_meshes(mesh.object_id, &mesh);
}

// `mesh` over mesh `index` (fits): its triangles keep their places, and in a built dynamic scene
// build() then refits the object's subtree.
void Scene::rewrite_mesh(uint32_t index, const MeshInput& mesh) {
  const bool in_leaves = meshes_.triangles.size() != meshes_.info.size();  // built: see release_triangles
  meshes_.rewrite(index, mesh, [&](uint32_t t) -> TriangleVertices& {
    return in_leaves ? leaf_prims_[slot_of_triangle_[t]].vertices : meshes_.triangles[t];
  });
  const MeshRecord& record = meshes_.meshes[index];
  if (in_leaves)  // (a refit copies the records again with the moved corners, where copied)
    for (uint32_t t = record.first_triangle; t < record.first_triangle + record.triangle_count; ++t)
      leaf_prims_[slot_of_triangle_[t]].visibility = mesh.visibility;
  if (in_leaves && geometry_built_ && dynamic_) {
    moved_objects_.push_back(mesh.object_id);
    invalidate_lights();
  } else {
    geometry_changed(mesh.object_id);
  }
}

// The meshes made anew without object `object`'s, `replacement` (if any) where its first one was: the
// triangle order stays that of a scene built with the replacement there.
void Scene::rebuild_meshes(uint32_t object, const MeshInput* replacement) {
  restore_triangles();
  MeshStore next;
  bool placed = replacement == nullptr;
  for (const MeshRecord& record : meshes_.meshes) {
    if (record.object != object) {
      next.append_copy(meshes_, record);
    } else if (!placed) {
      next.append(*replacement);
      placed = true;
    }
  }
  if (!placed) next.append(*replacement);
  meshes_ = std::move(next);
  geometry_changed(object);
}

size_t Scene::remove_object(uint32_t object) {
  ensure_mutable();
  size_t removed = 0;
  for (const MeshRecord& record : meshes_.meshes)
    if (record.object == object) removed += record.triangle_count;
  if (removed > 0) rebuild_meshes(object, nullptr);
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

std::vector<uint32_t> Scene::object_meshes(uint32_t object, const std::string& what) const {
  const std::vector<uint32_t> own = meshes_.meshes_of(object);
  for (const SphereInfo& s : spheres_)
    if (s.object == object) fail(what, "its object is not a triangle mesh alone");
  for (const RevolveSegment& r : revolve_segments_)
    if (r.object == object) fail(what, "its object is not a triangle mesh alone");
  if (own.empty()) fail(what, "object " + std::to_string(object) + " has no mesh in the scene");
  return own;
}

}  // namespace ppm
