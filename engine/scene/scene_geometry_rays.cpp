// Ray queries on a scene's built geometry, and what a hit reads of its primitive (see scene_geometry.h).
#include "scene/scene_geometry.h"

#include "geometry/bezier_revolve.h"
#include "geometry/object_bvh.h"

#include <algorithm>

namespace ppm {

namespace {

// How u and v change along a triangle: the gradients whose dot products with its edges give the
// UV differences along them (and zero along the normal).
void uv_gradients(const TrianglePrim& t, const glm::vec2* uv, Vec3& du, Vec3& dv) {
  const Vec3 n = glm::cross(t.e1, t.e2);
  const double det = glm::dot(n, n);
  if (!(det > 0.0)) return;
  const Vec3 b1 = glm::cross(t.e2, n) / det, b2 = glm::cross(n, t.e1) / det;
  const Vec2 d1 = Vec2(uv[1] - uv[0]), d2 = Vec2(uv[2] - uv[0]);
  du = d1.x * b1 + d2.x * b2;
  dv = d1.y * b1 + d2.y * b2;
}

}  // namespace

// Triangles, by far the most common, are tested inline; the rest out of line.
bool SceneGeometry::is_holdout(const Hit& hit) const {
  uint32_t id = hit.primitive;
  if (id < meshes_.triangle_count()) return meshes_.meshes[meshes_.info[id].mesh].visibility & kHoldoutFlag;
  id -= meshes_.triangle_count();
  if (id < spheres_.size()) return spheres_[id].visibility & kHoldoutFlag;
  id -= static_cast<uint32_t>(spheres_.size());
  return id < revolve_segments_.size() && (revolve_segments_[id].visibility & kHoldoutFlag);
}

inline bool SceneGeometry::intersect_slot(uint32_t slot, const Ray& ray, double& tmax, Hit& scratch) const {
  if (!copied_leaves_.empty()) {
    const CopiedLeaf& c = copied_leaves_[slot];
    if (!(c.leaf.visibility & ray.kind)) return false;
    if (c.leaf.kind != PrimitiveKind::Triangle) return intersect_non_triangle(slot, ray, tmax, scratch);
    return record_triangle_hit(slot, c.leaf.index, c.tri, ray, tmax, scratch);
  }
  const LeafPrim& p = leaf_prims_[slot];
  if (!(p.visibility & ray.kind)) return false;
  if (p.kind != PrimitiveKind::Triangle) return intersect_non_triangle(slot, ray, tmax, scratch);
  return record_triangle_hit(slot, p.index, meshes_.triangle(p.vertices), ray, tmax, scratch);
}

inline bool SceneGeometry::record_triangle_hit(uint32_t slot, uint32_t triangle, const TrianglePrim& tri, const Ray& ray,
                                       double& tmax, Hit& scratch) const {
  double t, b1, b2;
  if (!intersect_triangle(tri, ray, tmax, t, b1, b2)) return false;
  prefetch(&meshes_.info[triangle]);  // fill_hit reads it if this hit stays the closest
  tmax = t;
  scratch.t = t;
  scratch.primitive = slot;
  scratch.uv = Vec2(b1, b2);  // barycentrics until fill_hit
  return true;
}

bool SceneGeometry::intersect_non_triangle(uint32_t slot, const Ray& ray, double& tmax, Hit& scratch) const {
  const LeafPrim& p = leaf(slot);
  if (p.kind == PrimitiveKind::Sphere) {
    double t;
    if (!intersect_sphere(spheres_[p.index].sphere, ray, tmax, t)) return false;
    tmax = t;
    scratch.t = t;
    scratch.primitive = slot;
    return true;
  }
  const RevolveSegment& r = revolve_segments_[p.index];
  Hit h;
  if (!revolves_[r.revolve]->intersect_segment(r.segment, ray, 0.0, tmax, h)) return false;
  tmax = h.t;
  scratch = h;
  scratch.primitive = slot;
  return true;
}

bool SceneGeometry::intersect(const Ray& ray, Hit& hit, double tmax) const {
  Hit scratch;
  bvh_.closest(
      ray.origin, ray.direction, tmax, [&](uint32_t slot, double& t) { return intersect_slot(slot, ray, t, scratch); },
      [&](uint32_t first, uint32_t count) { prefetch_leaf(first, count); });
  if (!scratch.found()) return false;
  hit = scratch;
  fill_hit(ray, hit, scratch.uv.x, scratch.uv.y);
  return true;
}

void SceneGeometry::intersect_many(const Ray* rays, size_t count, Hit* hits) const {
  for (size_t i = 0; i < count; ++i) hits[i] = Hit{};
  if (!interleave_) {  // the BVH stays in cache: nothing to overlap, so no bookkeeping for it
    for (size_t i = 0; i < count; ++i) intersect(rays[i], hits[i]);
    return;
  }
  bvh_.closest_many(
      count, [&](size_t i) -> const Ray& { return rays[i]; },
      [&](size_t i, uint32_t slot, double& t) { return intersect_slot(slot, rays[i], t, hits[i]); },
      [&](uint32_t first, uint32_t n) { prefetch_leaf(first, n); },
      [&](size_t i) {
        if (hits[i].found()) fill_hit(rays[i], hits[i], hits[i].uv.x, hits[i].uv.y);
      });
}

bool SceneGeometry::occluded(const Ray& ray, double distance) const {
  Hit scratch;
  return bvh_.any(ray.origin, ray.direction, distance,
                  [&](uint32_t slot, double& t) { return intersect_slot(slot, ray, t, scratch); });
}

// `hit.primitive` holds the leaf slot on entry and the primitive id on return.
void SceneGeometry::fill_hit(const Ray& ray, Hit& hit, double b1, double b2) const {
  const uint32_t slot = hit.primitive;
  const LeafPrim& ref = leaf(slot);
  // Primitive ids number triangles, then spheres, then revolve segments.
  hit.primitive = ref.index;
  if (ref.kind != PrimitiveKind::Triangle) hit.primitive += meshes_.triangle_count();
  if (ref.kind == PrimitiveKind::BezierRevolve) hit.primitive += static_cast<uint32_t>(spheres_.size());
  switch (ref.kind) {
    case PrimitiveKind::Triangle: {
      TrianglePrim scratch;
      const TrianglePrim& t = leaf_triangle(slot, scratch);  // in cache from the test
      const TriangleInfo& info = meshes_.info[ref.index];
      const MeshRecord& mesh = meshes_.meshes[info.mesh];
      const double b0 = 1.0 - b1 - b2;
      auto corners = [&](const auto& values, const AttributeRange& range) {
        return meshes_.corners(values, range, mesh, ref.index, ref.vertices);
      };
      hit.position = t.v0 + b1 * t.e1 + b2 * t.e2;
      hit.geometric_normal = triangle_normal(t);
      hit.shading_normal = hit.geometric_normal;
      if (mesh.normals.present()) {
        const auto n = corners(meshes_.normals, mesh.normals);
        const Vec3 ns = b0 * Vec3(n[0]) + b1 * Vec3(n[1]) + b2 * Vec3(n[2]);
        const double len = glm::length(ns);
        if (len > 0.0) hit.shading_normal = ns / len;
        // Keep the shading normal in the geometric hemisphere (flipped winding).
        if (glm::dot(hit.shading_normal, hit.geometric_normal) < 0.0) hit.geometric_normal = -hit.geometric_normal;
      }
      hit.uv = Vec2(0.0);
      if (mesh.uvs.present()) {
        const auto uv = corners(meshes_.uvs, mesh.uvs);
        hit.uv = b0 * Vec2(uv[0]) + b1 * Vec2(uv[1]) + b2 * Vec2(uv[2]);
      }
      hit.tangent = glm::vec4(0.0f);
      if (mesh.tangents.present()) {  // interpolated as Cycles does, not re-orthogonalised
        const auto tangent = corners(meshes_.tangents, mesh.tangents);
        hit.tangent = static_cast<float>(b0) * tangent[0] + static_cast<float>(b1) * tangent[1] +
                      static_cast<float>(b2) * tangent[2];
        hit.tangent.w = tangent[0].w;
      }
      hit.material = info.material;
      hit.object = mesh.object;
      break;
    }
    case PrimitiveKind::Sphere: {
      const SphereInfo& s = spheres_[ref.index];
      const Vec3 n = glm::normalize(ray.origin + hit.t * ray.direction - s.sphere.center);
      hit.position = s.sphere.center + s.sphere.radius * n;  // on the surface, not off by t's error
      hit.geometric_normal = hit.shading_normal = n;
      hit.uv = Vec2(0.5 + std::atan2(n.y, n.x) / (2.0 * kPi), 0.5 + std::asin(glm::clamp(n.z, -1.0, 1.0)) / kPi);
      hit.material = s.material;
      hit.object = s.object;
      break;
    }
    case PrimitiveKind::BezierRevolve: {
      const RevolveSegment& r = revolve_segments_[ref.index];
      hit.material = r.material;
      hit.object = r.object;
      break;
    }
  }
}

void SceneGeometry::add_primitive_data(const NodeProgram::Needs& needs, uint32_t primitive, const Vec3& position,
                                       ShadingContext& c) const {
  if (primitive >= meshes_.triangle_count()) return;  // primitive ids number the triangles first
  if (!needs.uv_gradients && !needs.attribute) return;
  const MeshRecord& mesh = meshes_.meshes[meshes_.info[primitive].mesh];
  const TriangleVertices& v = triangle_vertices(primitive);
  const TrianglePrim t = meshes_.triangle(v);
  auto corners = [&](const auto& values, const AttributeRange& range) {
    return meshes_.corners(values, range, mesh, primitive, v);
  };
  if (needs.uv_gradients && mesh.uvs.present()) uv_gradients(t, corners(meshes_.uvs, mesh.uvs).data(), c.du_dp, c.dv_dp);
  if (needs.attribute && mesh.colors.present()) {
    // Barycentric coordinates of the point: the dual basis of the edges (as uv_gradients).
    const Vec3 n = glm::cross(t.e1, t.e2);
    const double det = glm::dot(n, n);
    if (!(det > 0.0)) return;
    const Vec3 d = position - t.v0;
    const double b1 = glm::dot(glm::cross(t.e2, n), d) / det, b2 = glm::dot(glm::cross(n, t.e1), d) / det;
    const auto a = corners(meshes_.colors, mesh.colors);
    c.attribute = float(1.0 - b1 - b2) * a[0] + float(b1) * a[1] + float(b2) * a[2];
  }
}

std::array<Vec3, 3> SceneGeometry::triangle_corners(uint32_t triangle) const {
  const TriangleVertices& v = triangle_vertices(triangle);
  return {meshes_.vertices[v.v[0]], meshes_.vertices[v.v[1]], meshes_.vertices[v.v[2]]};
}

std::array<Vec2, 3> SceneGeometry::triangle_uvs(uint32_t triangle) const {
  const MeshRecord& mesh = meshes_.meshes[meshes_.info[triangle].mesh];
  if (!mesh.uvs.present()) return {Vec2(0.0), Vec2(0.0), Vec2(0.0)};
  const auto uv = meshes_.corners(meshes_.uvs, mesh.uvs, mesh, triangle, triangle_vertices(triangle));
  return {Vec2(uv[0]), Vec2(uv[1]), Vec2(uv[2])};
}

bool SceneGeometry::spheres_use(uint32_t material) const {
  return std::any_of(spheres_.begin(), spheres_.end(), [&](const SphereInfo& s) { return s.material == material; });
}

bool SceneGeometry::revolves_use(uint32_t material) const {
  return std::any_of(revolve_segments_.begin(), revolve_segments_.end(),
                     [&](const RevolveSegment& r) { return r.material == material; });
}

size_t SceneGeometry::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  size_t b = meshes_.memory_bytes() + bytes(copied_leaves_) + bytes(spheres_) + bytes(revolve_segments_) +
             bytes(slot_of_triangle_) + bytes(leaf_prims_) + bytes(bvh_.nodes()) + bytes(bvh_.prim_order());
  if (object_bvh_) b += object_bvh_->memory_bytes();
  return b;
}

}  // namespace ppm
