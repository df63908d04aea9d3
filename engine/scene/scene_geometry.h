// What rays hit: a scene's primitives (triangle meshes, spheres, Bézier revolves), each with its
// material, object id and ray visibility, under one BVH, and the ray queries on them. The Scene owns
// one; it checks what refers outside the geometry (material indices, emissive materials) before it
// adds a primitive here, and prepares its lights and media from what this holds once built.
//
// Building is incremental: edits mark what changed, and build() makes the BVH again, or in a dynamic
// scene only the subtrees of the objects that changed (refitting those moved in place).
#pragma once

#include "geometry/bvh.h"
#include "geometry/ray.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"
#include "scene/mesh_store.h"
#include "shading/node_program.h"

#include <array>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace ppm {

class BezierRevolve;
class ObjectBvh;

// What a walk reads (BVH nodes and the leaf tests' records, with the vertices they name where the
// triangles are not copied) above which intersect_many interleaves rays' walks. Below it the BVH
// stays in a core's cache, there are no misses to overlap, and the bookkeeping only costs. Measured
// on the 2-core EPYC (2 MB L2 per core), asteroid meshes of bench/run.py raycast, with 80-byte leaf
// records: up to 7,500 triangles (about 0.7 MB) cast 0-11% faster one ray at a time, 30,000 (about
// 3 MB) broke even, and 99,372 (about 10 MB) gained 18-32%.
constexpr double kInterleaveBytes = 2.0 * 1024 * 1024;

// How a built scene keeps its triangles for the ray tests: beside its leaf records, a copy of each
// triangle's corners in leaf order with its record (Copies: 96 bytes a triangle more; a leaf's test
// reads one stretch of memory), or only the indices of its mesh's shared vertices (Compact: a
// dependent read more a triangle; random rays through bench/run.py raycast's 10^6-triangle terrain
// measured 30% slower). Auto copies up to kCopiedTrianglesMax triangles. Both find the same hits,
// bit for bit.
enum class GeometryLayout { Auto, Copies, Compact };
constexpr size_t kCopiedTrianglesMax = 4'000'000;

class SceneGeometry {
 public:
  SceneGeometry();
  ~SceneGeometry();
  SceneGeometry(SceneGeometry&&) noexcept;
  SceneGeometry& operator=(SceneGeometry&&) noexcept;

  // ---- Editing (scene_geometry.cpp). `what` names the object in errors (std::invalid_argument). ----
  // Checks `mesh`'s arrays (finite, indices in range, attribute counts) but not its material indices.
  void add_mesh(const MeshInput& mesh, const std::string& what);
  // The triangles of object `mesh.object_id` (it has no other primitives) become `mesh`'s: moved, or
  // reshaped with any number of triangles and attributes, in the place of the object's first triangle.
  // Moved with as many triangles and vertices and the same attributes, a built dynamic scene's build()
  // refits the object's BVH subtree; otherwise it builds that subtree again and keeps the others'.
  void replace_mesh(const MeshInput& mesh, const std::string& what);
  // Removes every primitive of object `object`; returns how many there were.
  size_t remove_object(uint32_t object);
  void add_sphere(const SpherePrim& sphere, uint32_t material, uint32_t object, uint8_t visibility);
  void add_revolve(const std::vector<Vec2>& points, bool cubic_chain, const Mat4& object_to_world,
                   uint32_t material, uint32_t object, uint8_t visibility, const std::string& what);
  // A dynamic scene builds its BVH object by object (geometry/object_bvh.h): slower to trace where
  // objects overlap, but an object's mesh can then be replaced in place. The setters return whether
  // they changed anything (the geometry is then built again).
  bool set_dynamic(bool dynamic);
  bool dynamic() const { return dynamic_; }
  bool set_layout(GeometryLayout layout);
  GeometryLayout layout() const { return layout_; }

  // ---- Building. ----
  bool built() const { return built_ && moved_objects_.empty() && changed_objects_.empty(); }
  // Makes the BVH and the leaf records where an edit asks for it; returns whether it changed anything.
  bool build();
  bool triangles_copied() const { return !copied_leaves_.empty(); }  // the built geometry's choice
  // How many objects' subtrees the last build() of a dynamic scene built (the others were kept).
  uint32_t subtrees_built() const { return subtrees_built_; }

  // ---- Ray queries on the built geometry (scene_geometry_rays.cpp). ----
  // Closest hit with 0 < t < tmax; fills the hit record.
  bool intersect(const Ray& ray, Hit& hit, double tmax = kInf) const;
  // Closest hits of `count` rays (t > 0), the same as intersect() ray by ray. When the BVH is larger
  // than kInterleaveBytes, several rays' traversals are interleaved to overlap their cache misses
  // (Bvh::closest_many). A miss leaves hits[i].found() false.
  void intersect_many(const Ray* rays, size_t count, Hit* hits) const;
  bool interleaves_walks() const { return interleave_; }
  // Is anything in the way over (0, distance)?
  bool occluded(const Ray& ray, double distance) const;
  // Is the hit primitive part of a Holdout object (its visibility carries kHoldoutFlag)?
  bool is_holdout(const Hit& hit) const;
  double offset_floor() const { return offset_floor_; }  // see ray_offset()
  Aabb bounds() const { return bvh_.bounds(); }

  // ---- The primitives. Primitive ids number the triangles, then the spheres, then the revolve
  // segments (Hit::primitive). ----
  uint32_t triangle_count() const { return meshes_.triangle_count(); }
  size_t primitive_count() const { return meshes_.info.size() + spheres_.size() + revolve_segments_.size(); }
  TrianglePrim triangle(uint32_t triangle) const { return meshes_.triangle(triangle_vertices(triangle)); }
  std::array<Vec3, 3> triangle_corners(uint32_t triangle) const;  // as the mesh stores them
  uint32_t triangle_material(uint32_t triangle) const { return meshes_.info[triangle].material; }
  uint32_t triangle_object(uint32_t triangle) const { return meshes_.meshes[meshes_.info[triangle].mesh].object; }
  // A triangle's UVs at its corners (zero without a UV map).
  std::array<Vec2, 3> triangle_uvs(uint32_t triangle) const;
  bool spheres_use(uint32_t material) const;   // does a sphere have material `material`?
  bool revolves_use(uint32_t material) const;  // does a revolve?
  // `f(material, object, box)` for each primitive, triangles first.
  template <class F>
  void for_each_primitive_box(F&& f) const;
  // What a node program reads of primitive `primitive` at `position` on it: the UV gradients (a
  // Bump's steps) and the mesh attribute there, where `needs` asks for them.
  void add_primitive_data(const NodeProgram::Needs& needs, uint32_t primitive, const Vec3& position,
                          ShadingContext& c) const;
  // Primitives, their attributes, the BVH and its leaf records.
  size_t memory_bytes() const;

 private:
  struct PrimRef {
    PrimitiveKind kind;
    uint32_t index;  // into meshes_.info, spheres_ or revolve segments
  };
  struct SphereInfo {
    SpherePrim sphere;
    uint32_t material, object;
    uint8_t visibility;
  };
  struct RevolveSegment {
    uint32_t revolve, segment, material, object;
    uint8_t visibility;
  };
  // One record per BVH leaf slot (see Bvh::prim_order), in leaf order: a leaf's primitives sit side
  // by side, and a triangle's record holds its vertices' indices, so testing a leaf reads its records
  // and the vertices (shared by the mesh's triangles) they name.
  struct LeafPrim {
    TriangleVertices vertices;  // triangles only
    uint32_t index;             // into meshes_.info, spheres_ or revolve_segments_
    PrimitiveKind kind;
    uint8_t visibility;  // RayKinds that see it
  };
  // A leaf slot's record with its triangle's corners copied (GeometryLayout::Copies): all the ray
  // test and fill_hit read, a leaf's in one stretch of memory (leaf_prims_ are kept for the rest).
  struct CopiedLeaf {
    TrianglePrim tri;  // triangles only
    LeafPrim leaf;
  };

  // Editing.
  std::vector<uint32_t> object_meshes(uint32_t object, const std::string& what) const;
  void rewrite_mesh(uint32_t index, const MeshInput& mesh);
  void rebuild_meshes(uint32_t object, const MeshInput* replacement);
  void drop_unused_revolves();
  void changed(uint32_t object);
  void invalidate() { built_ = false; }
  // A triangle's vertex indices: in meshes_.triangles, or once built in its leaf record.
  const TriangleVertices& triangle_vertices(uint32_t triangle) const;
  void restore_triangles();
  void release_triangles();

  // Building.
  void build_bvh();
  void build_object_bvh(const std::vector<Aabb>& boxes, bool reuse_unchanged);
  void refit_moved_objects();
  void finish();  // after the BVH changed: its derived figures
  void order_vertices_by_leaf();
  bool copies_triangles() const;  // what the layout asks of the next build
  void copy_leaf_triangles();
  PrimRef prim_ref(uint32_t primitive) const;
  Aabb primitive_box(const PrimRef& ref) const;
  uint32_t object_of(const PrimRef& ref) const;
  uint32_t material_of(const PrimRef& ref) const;
  uint8_t visibility_of(const PrimRef& ref) const;

  // Ray tests.
  const LeafPrim& leaf(uint32_t slot) const {
    return copied_leaves_.empty() ? leaf_prims_[slot] : copied_leaves_[slot].leaf;
  }
  // The triangle at a leaf slot, from its copy or its vertices (`scratch` holds the latter).
  const TrianglePrim& leaf_triangle(uint32_t slot, TrianglePrim& scratch) const {
    if (!copied_leaves_.empty()) return copied_leaves_[slot].tri;
    scratch = meshes_.triangle(leaf_prims_[slot].vertices);
    return scratch;
  }
  // Tests the primitive at a leaf slot; on a closer hit lowers tmax and records the slot in
  // scratch.primitive (fill_hit turns it into the id).
  bool intersect_slot(uint32_t slot, const Ray& ray, double& tmax, Hit& scratch) const;
  bool record_triangle_hit(uint32_t slot, uint32_t triangle, const TrianglePrim& tri, const Ray& ray, double& tmax,
                           Hit& scratch) const;
  bool intersect_non_triangle(uint32_t slot, const Ray& ray, double& tmax, Hit& scratch) const;
  // Every cache line of a leaf's records, asked for when its box is hit.
  void prefetch_leaf(uint32_t first, uint32_t count) const {
    if (copied_leaves_.empty())
      prefetch_lines(&leaf_prims_[first], count * sizeof(LeafPrim));
    else
      prefetch_lines(&copied_leaves_[first], count * sizeof(CopiedLeaf));
  }
  void fill_hit(const Ray& ray, Hit& hit, double b1, double b2) const;

  MeshStore meshes_;
  std::vector<SphereInfo> spheres_;
  std::vector<std::unique_ptr<BezierRevolve>> revolves_;
  std::vector<RevolveSegment> revolve_segments_;

  std::vector<uint32_t> slot_of_triangle_;  // once built: each triangle's leaf slot (meshes_.triangles is then empty)
  Bvh bvh_;
  HugePageFillVector<LeafPrim> leaf_prims_;
  HugePageFillVector<CopiedLeaf> copied_leaves_;  // by slot; empty: the Compact layout
  GeometryLayout layout_ = GeometryLayout::Auto;
  bool dynamic_ = false;
  std::unique_ptr<ObjectBvh> object_bvh_;                // a dynamic scene's, once built
  std::unordered_map<uint32_t, uint32_t> object_group_;  // object id -> its index in object_bvh_
  // Object ids since the BVH was last made: moved or reshaped in place (their subtrees refitted), and
  // with primitives added, removed or replaced (their subtrees built again, the others kept).
  std::vector<uint32_t> moved_objects_, changed_objects_;
  uint32_t subtrees_built_ = 0;
  double offset_floor_ = 1e-12;
  bool interleave_ = false;  // BVH larger than kInterleaveBytes
  bool built_ = false;       // the BVH and its leaf records
};

template <class F>
void SceneGeometry::for_each_primitive_box(F&& f) const {
  for (uint32_t i = 0; i < primitive_count(); ++i) {
    const PrimRef ref = prim_ref(i);
    f(material_of(ref), object_of(ref), primitive_box(ref));
  }
}

}  // namespace ppm
