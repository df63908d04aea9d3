// Building a scene's geometry: primitives added, replaced and removed, and the BVH made again where
// they changed (see scene_geometry.h).
#include "scene/scene_geometry.h"

#include "base/freed_memory.h"
#include "base/parallel.h"
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

SceneGeometry::SceneGeometry() = default;
SceneGeometry::~SceneGeometry() = default;
SceneGeometry::SceneGeometry(SceneGeometry&&) noexcept = default;
SceneGeometry& SceneGeometry::operator=(SceneGeometry&&) noexcept = default;

void SceneGeometry::add_mesh(const MeshInput& mesh, const std::string& what) {
  check_arrays(mesh, what);
  check_room(meshes_, mesh, what);
  restore_triangles();
  meshes_.append(mesh);
  changed(mesh.object_id);
}

void SceneGeometry::replace_mesh(const MeshInput& mesh, const std::string& what) {
  check_arrays(mesh, what);
  check_room(meshes_, mesh, what);
  const std::vector<uint32_t> own = object_meshes(mesh.object_id, what);
  if (own.size() == 1 && fits(meshes_.meshes[own[0]], mesh))
    rewrite_mesh(own[0], mesh);
  else
    rebuild_meshes(mesh.object_id, &mesh);
}

// `mesh` over mesh `index` (fits): its triangles keep their places, and in a built dynamic scene
// build() then refits the object's subtree.
void SceneGeometry::rewrite_mesh(uint32_t index, const MeshInput& mesh) {
  const bool in_leaves = meshes_.triangles.size() != meshes_.info.size();  // built: see release_triangles
  meshes_.rewrite(index, mesh, [&](uint32_t t) -> TriangleVertices& {
    return in_leaves ? leaf_prims_[slot_of_triangle_[t]].vertices : meshes_.triangles[t];
  });
  const MeshRecord& record = meshes_.meshes[index];
  if (in_leaves)  // (a refit copies the records again with the moved corners, where copied)
    for (uint32_t t = record.first_triangle; t < record.first_triangle + record.triangle_count; ++t)
      leaf_prims_[slot_of_triangle_[t]].visibility = mesh.visibility;
  if (in_leaves && built_ && dynamic_)
    moved_objects_.push_back(mesh.object_id);
  else
    changed(mesh.object_id);
}

// The meshes made anew without object `object`'s, `replacement` (if any) where its first one was: the
// triangle order stays that of a scene built with the replacement there.
void SceneGeometry::rebuild_meshes(uint32_t object, const MeshInput* replacement) {
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
  changed(object);
}

size_t SceneGeometry::remove_object(uint32_t object) {
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
  if (removed > 0) changed(object);
  return removed;
}

// The revolves no segment refers to any more go; the segments' indices follow.
void SceneGeometry::drop_unused_revolves() {
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
void SceneGeometry::changed(uint32_t object) {
  if (dynamic_ && built_)
    changed_objects_.push_back(object);
  else
    invalidate();
}

std::vector<uint32_t> SceneGeometry::object_meshes(uint32_t object, const std::string& what) const {
  const std::vector<uint32_t> own = meshes_.meshes_of(object);
  for (const SphereInfo& s : spheres_)
    if (s.object == object) fail(what, "its object is not a triangle mesh alone");
  for (const RevolveSegment& r : revolve_segments_)
    if (r.object == object) fail(what, "its object is not a triangle mesh alone");
  if (own.empty()) fail(what, "object " + std::to_string(object) + " has no mesh in the scene");
  return own;
}

void SceneGeometry::add_sphere(const SpherePrim& sphere, uint32_t material, uint32_t object, uint8_t visibility) {
  spheres_.push_back(SphereInfo{sphere, material, object, visibility});
  changed(object);
}

void SceneGeometry::add_revolve(const std::vector<Vec2>& points, bool cubic_chain, const Mat4& object_to_world,
                                uint32_t material, uint32_t object, uint8_t visibility, const std::string& what) {
  try {
    revolves_.push_back(std::make_unique<BezierRevolve>(
        points, cubic_chain ? BezierProfileKind::CubicChain : BezierProfileKind::SingleCurve, object_to_world));
  } catch (const std::invalid_argument& e) {
    std::string message = e.what();
    const std::string prefix = "BezierRevolve: ";
    if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
    fail(what, message);
  }
  for (size_t s = 0; s < revolves_.back()->segment_count(); ++s) {
    const Aabb b = revolves_.back()->segment_bounds(s);
    if (!is_finite(b.lo) || !is_finite(b.hi) || max_abs(b.lo) > kMaxCoordinate || max_abs(b.hi) > kMaxCoordinate) {
      revolves_.pop_back();
      fail(what, "the surface reaches beyond the supported " + number(kMaxCoordinate) + " m from the origin");
    }
  }
  const uint32_t index = static_cast<uint32_t>(revolves_.size() - 1);
  for (size_t s = 0; s < revolves_.back()->segment_count(); ++s)
    revolve_segments_.push_back(RevolveSegment{index, static_cast<uint32_t>(s), material, object, visibility});
  changed(object);
}

// A built scene keeps its triangles' vertex indices in the BVH's leaf records only (12 bytes a
// triangle less); they come back in triangle order before the scene changes or is built again.
void SceneGeometry::restore_triangles() {
  std::vector<TriangleVertices>& triangles = meshes_.triangles;
  if (triangles.size() == meshes_.info.size()) return;
  triangles.resize(meshes_.info.size());
  for (size_t i = 0; i < triangles.size(); ++i) triangles[i] = leaf_prims_[slot_of_triangle_[i]].vertices;
}

const TriangleVertices& SceneGeometry::triangle_vertices(uint32_t triangle) const {
  const std::vector<TriangleVertices>& triangles = meshes_.triangles;
  return triangles.size() == meshes_.info.size() ? triangles[triangle] : leaf_prims_[slot_of_triangle_[triangle]].vertices;
}

// After the build: the triangles are found through their leaf slots. What the build freed (the
// triangle-ordered copy, the build's boxes and node lists, some in the arenas of the threads that
// built subtrees) goes back to the system: glibc keeps freed memory resident otherwise, 70 bytes a
// triangle of a 10^6-triangle mesh.
void SceneGeometry::release_triangles() {
  slot_of_triangle_.resize(meshes_.triangles.size());
  for (uint32_t slot = 0; slot < leaf_prims_.size(); ++slot)
    if (leaf_prims_[slot].kind == PrimitiveKind::Triangle) slot_of_triangle_[leaf_prims_[slot].index] = slot;
  std::vector<TriangleVertices>().swap(meshes_.triangles);
  meshes_.shrink_to_fit();
  return_freed_memory();
}

bool SceneGeometry::build() {
  if (!built_ || !changed_objects_.empty()) {
    build_bvh();
    return true;
  }
  if (moved_objects_.empty()) return false;
  refit_moved_objects();
  return true;
}

void SceneGeometry::build_bvh() {
  restore_triangles();
  const std::vector<TriangleVertices>& triangles = meshes_.triangles;
  const auto box_of = [&](size_t i) { return primitive_box(prim_ref(static_cast<uint32_t>(i))); };
  if (dynamic_) {
    std::vector<Aabb> boxes(primitive_count());
    for (size_t i = 0; i < boxes.size(); ++i) boxes[i] = box_of(i);
    build_object_bvh(boxes, built_);
  } else {
    object_bvh_.reset();
    bvh_.build(primitive_count(), box_of);  // the boxes made on the build's threads, never stored
  }
  moved_objects_.clear();
  changed_objects_.clear();
  const std::vector<uint32_t>& order = bvh_.prim_order();
  leaf_prims_.resize(order.size());  // unwritten (HugePageFillVector)
  parallel_for(hardware_threads(), order.size(), [&](size_t begin, size_t end) {
    for (size_t slot = begin; slot < end; ++slot) {
      const PrimRef ref = prim_ref(order[slot]);
      const TriangleVertices vertices = ref.kind == PrimitiveKind::Triangle ? triangles[ref.index] : TriangleVertices{};
      leaf_prims_[slot] = LeafPrim{vertices, ref.index, ref.kind, visibility_of(ref)};
    }
  });
  bvh_.release_prim_order();  // the leaf records are in slot order
  if (copies_triangles()) {
    copy_leaf_triangles();
  } else {
    HugePageFillVector<CopiedLeaf>().swap(copied_leaves_);
    if (!dynamic_) order_vertices_by_leaf();  // only the Compact layout's ray tests read the vertices
  }
  finish();
  release_triangles();
  built_ = true;
}

bool SceneGeometry::copies_triangles() const {
  return layout_ == GeometryLayout::Copies ||
         (layout_ == GeometryLayout::Auto && meshes_.triangle_count() <= kCopiedTrianglesMax);
}

// Written on every thread, the page faults too (huge pages: the kernel's compaction to find them):
// 960 MB of copies at 10^7 triangles took 1.5-2.1 s to resize on one thread.
void SceneGeometry::copy_leaf_triangles() {
  copied_leaves_.resize(leaf_prims_.size());  // unwritten (HugePageFillVector)
  parallel_for(hardware_threads(), leaf_prims_.size(), [&](size_t begin, size_t end) {
    for (size_t slot = begin; slot < end; ++slot) {
      const LeafPrim& p = leaf_prims_[slot];
      copied_leaves_[slot] =
          CopiedLeaf{p.kind == PrimitiveKind::Triangle ? meshes_.triangle(p.vertices) : TrianglePrim{}, p};
    }
  });
}

bool SceneGeometry::set_layout(GeometryLayout layout) {
  if (layout == layout_) return false;
  restore_triangles();
  layout_ = layout;
  invalidate();
  return true;
}

// Each mesh's vertices in the order the BVH leaves first name them, so that a leaf's triangles find
// their vertices side by side (in the input's order they may lie anywhere in the mesh: random rays
// through a 1.3 x 10^6-triangle grid and soup traced about 15% slower so, in the Compact layout). A
// dynamic scene keeps the input's order, which replace_mesh writes in place.
void SceneGeometry::order_vertices_by_leaf() {
  constexpr uint32_t kUnseen = UINT32_MAX;
  std::vector<uint32_t> position(meshes_.vertices.size(), kUnseen), next(meshes_.meshes.size());
  for (size_t m = 0; m < next.size(); ++m) next[m] = meshes_.meshes[m].first_vertex;
  for (const LeafPrim& p : leaf_prims_) {
    if (p.kind != PrimitiveKind::Triangle) continue;
    const uint32_t mesh = meshes_.info[p.index].mesh;
    for (uint32_t v : p.vertices.v)
      if (position[v] == kUnseen) position[v] = next[mesh]++;
  }
  for (size_t m = 0; m < next.size(); ++m) {  // vertices no triangle uses, at their mesh's end
    const MeshRecord& r = meshes_.meshes[m];
    for (uint32_t v = r.first_vertex; v < r.first_vertex + r.vertex_count; ++v)
      if (position[v] == kUnseen) position[v] = next[m]++;
  }
  meshes_.reorder_vertices(position);
  parallel_for(hardware_threads(), leaf_prims_.size(), [&](size_t begin, size_t end) {
    for (size_t slot = begin; slot < end; ++slot)
      if (leaf_prims_[slot].kind == PrimitiveKind::Triangle)
        for (uint32_t& v : leaf_prims_[slot].vertices.v) v = position[v];
  });
}

// Groups the primitives by object id and builds their BVH object by object; with `reuse_unchanged`
// (the BVH was built and only some objects changed since) the others keep their subtrees.
void SceneGeometry::build_object_bvh(const std::vector<Aabb>& boxes, bool reuse_unchanged) {
  std::unordered_map<uint32_t, uint32_t> previous;
  previous.swap(object_group_);
  std::vector<uint32_t> group(boxes.size());
  for (uint32_t i = 0; i < group.size(); ++i) {
    const uint32_t object = object_of(prim_ref(i));
    group[i] = object_group_.emplace(object, static_cast<uint32_t>(object_group_.size())).first->second;
  }
  std::vector<int32_t> reuse;
  if (reuse_unchanged && object_bvh_) {
    std::vector<uint32_t> edited = moved_objects_;
    edited.insert(edited.end(), changed_objects_.begin(), changed_objects_.end());
    std::sort(edited.begin(), edited.end());
    reuse.assign(object_group_.size(), -1);
    for (const auto& [object, g] : object_group_) {
      const auto old = previous.find(object);
      if (old != previous.end() && !std::binary_search(edited.begin(), edited.end(), object))
        reuse[g] = static_cast<int32_t>(old->second);
    }
  } else {
    object_bvh_ = std::make_unique<ObjectBvh>();
  }
  subtrees_built_ = object_bvh_->build(boxes, group, static_cast<uint32_t>(object_group_.size()), reuse);
  bvh_.build_from_tree(object_bvh_->joined());
}

// The objects replace_mesh moved: their subtrees refit, the tree over them built again.
void SceneGeometry::refit_moved_objects() {
  std::sort(moved_objects_.begin(), moved_objects_.end());
  moved_objects_.erase(std::unique(moved_objects_.begin(), moved_objects_.end()), moved_objects_.end());
  std::vector<Aabb> boxes;
  for (uint32_t object : moved_objects_) {
    const uint32_t g = object_group_.at(object);
    const uint32_t first = object_bvh_->first_slot(g);
    boxes.resize(object_bvh_->slot_count(g));
    for (size_t k = 0; k < boxes.size(); ++k) {
      const TrianglePrim t = meshes_.triangle(leaf_prims_[first + k].vertices);
      if (!copied_leaves_.empty()) copied_leaves_[first + k] = CopiedLeaf{t, leaf_prims_[first + k]};
      boxes[k] = triangle_box(t);
    }
    object_bvh_->refit(g, boxes);
  }
  bvh_.build_from_tree(object_bvh_->joined());
  bvh_.release_prim_order();
  finish();
  moved_objects_.clear();
  subtrees_built_ = 0;
}

void SceneGeometry::finish() {
  const size_t leaves = copied_leaves_.empty()
                            ? leaf_prims_.size() * sizeof(LeafPrim) + meshes_.vertices.size() * sizeof(Vec3)
                            : copied_leaves_.size() * sizeof(CopiedLeaf);
  interleave_ = bvh_.nodes().size() * sizeof(BvhNode) + leaves > kInterleaveBytes;  // what a walk reads
  const Aabb bounds = bvh_.bounds();
  offset_floor_ = bounds.empty() ? 1e-12 : 1e-10 * max_abs(bounds.extent()) + 1e-300;
}

bool SceneGeometry::set_dynamic(bool dynamic) {
  if (dynamic == dynamic_) return false;
  restore_triangles();
  dynamic_ = dynamic;
  invalidate();
  return true;
}

// Primitive i of a build: the triangles in order, then the spheres, then the revolve segments.
SceneGeometry::PrimRef SceneGeometry::prim_ref(uint32_t i) const {
  const uint32_t triangles = static_cast<uint32_t>(meshes_.info.size());
  const uint32_t spheres = static_cast<uint32_t>(spheres_.size());
  if (i < triangles) return {PrimitiveKind::Triangle, i};
  if (i < triangles + spheres) return {PrimitiveKind::Sphere, i - triangles};
  return {PrimitiveKind::BezierRevolve, i - triangles - spheres};
}

Aabb SceneGeometry::primitive_box(const PrimRef& ref) const {
  switch (ref.kind) {
    case PrimitiveKind::Triangle: return triangle_box(triangle(ref.index));
    case PrimitiveKind::Sphere: {
      const SpherePrim& s = spheres_[ref.index].sphere;
      return Aabb{s.center - Vec3(s.radius), s.center + Vec3(s.radius)};
    }
    default: {
      const RevolveSegment& r = revolve_segments_[ref.index];
      return revolves_[r.revolve]->segment_bounds(r.segment);
    }
  }
}

uint32_t SceneGeometry::object_of(const PrimRef& ref) const {
  switch (ref.kind) {
    case PrimitiveKind::Triangle: return triangle_object(ref.index);
    case PrimitiveKind::Sphere: return spheres_[ref.index].object;
    default: return revolve_segments_[ref.index].object;
  }
}

uint32_t SceneGeometry::material_of(const PrimRef& ref) const {
  switch (ref.kind) {
    case PrimitiveKind::Triangle: return triangle_material(ref.index);
    case PrimitiveKind::Sphere: return spheres_[ref.index].material;
    default: return revolve_segments_[ref.index].material;
  }
}

uint8_t SceneGeometry::visibility_of(const PrimRef& ref) const {
  switch (ref.kind) {
    case PrimitiveKind::Triangle: return meshes_.meshes[meshes_.info[ref.index].mesh].visibility;
    case PrimitiveKind::Sphere: return spheres_[ref.index].visibility;
    default: return revolve_segments_[ref.index].visibility;
  }
}

}  // namespace ppm
