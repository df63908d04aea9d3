// Scene building, validation and ray queries (see scene.h).
#include "scene/scene.h"

#include "geometry/bezier_revolve.h"
#include "geometry/object_bvh.h"
#include "math/sampling.h"
#include "base/freed_memory.h"
#include "base/parallel.h"
#include "scene/input_checks.h"
#include "shading/valid_reflection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <stdexcept>


namespace ppm {
using namespace scene_input;

void Scene::ensure_mutable() const {
  if (leases_.count.load() > 0)
    throw std::runtime_error("scene: cannot change a scene while a Renderer uses it; build a new Scene");
}

void Scene::invalidate() {
  geometry_built_ = false;
  lights_built_ = false;
}

// The lights and the world are prepared after the BVH, from it: changing them keeps the BVH.
void Scene::invalidate_lights() {
  lights_built_ = false;
}

void Scene::remove_lights() {
  ensure_mutable();
  user_lights_.clear();
  invalidate_lights();
}

void Scene::remove_textures_from(size_t count) {
  ensure_mutable();
  if (count >= textures_.size()) return;
  for (const Material& m : materials_) {
    const std::string what = quoted("material", m.name);
    if (m.texture >= 0 && static_cast<size_t>(m.texture) >= count)
      fail(what, "uses texture " + std::to_string(m.texture) + ", which would be removed");
    try {
      m.program.validate(count, what);
    } catch (const std::invalid_argument&) {
      fail(what, "reads a texture from " + std::to_string(count) + " on, which would be removed");
    }
  }
  textures_.erase(textures_.begin() + static_cast<std::ptrdiff_t>(count), textures_.end());
  background_ = Color(0.0);
  environment_input_.reset();
  environment_.reset();
  camera_environment_input_.reset();
  camera_environment_.reset();
  invalidate_lights();
}

Scene::Scene() = default;
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;

// A material's program is valid and what refers to its outputs is in range; returns the most each
// output can scale a colour by (+inf: unknown).
std::vector<double> Scene::check_inputs(const Material& m, const std::string& what) const {
  const NodeProgram& p = m.program;
  if (p.outputs.size() > static_cast<size_t>(kMaxInputs))
    fail(what, "a material takes at most " + std::to_string(kMaxInputs) + " inputs");
  p.validate(textures_.size(), what);
  std::vector<double> gain;
  for (size_t i = 0; i < p.outputs.size(); ++i) gain.push_back(p.output_bound(i, textures_));
  const int count = static_cast<int>(p.outputs.size());
  if (m.normal_map.input >= count)
    fail(what, "normal_map refers to input " + std::to_string(m.normal_map.input) + ", which the material does not have");
  if (!std::isfinite(m.normal_map.strength)) fail(what, "normal_map strength must be a finite number");
  if (m.emission_input >= count)
    fail(what, "emission_input refers to input " + std::to_string(m.emission_input) + ", which the material does not have");
  return gain;
}

// A mixture's lobes: in range, at most kMaxLobes, layers prepared; base_color becomes their summed
// colour (a bound of the albedo, for the energy check and the scene analysis).
void Scene::check_lobes(Material& m, const std::string& what) const {
  if (m.lobes.empty() || m.lobes.size() > static_cast<size_t>(kMaxLobes))
    fail(what, "a mixture needs 1 to " + std::to_string(kMaxLobes) + " lobes");
  std::vector<double> gain = check_inputs(m, what);
  Color bound(0.0);
  for (size_t i = 0; i < m.lobes.size(); ++i) {
    Lobe& l = m.lobes[i];
    const std::string lobe = "lobe " + std::to_string(i);
    for (const InputRef* ref : {&l.color_input, &l.roughness_input, &l.weight_inputs[0], &l.weight_inputs[1]})
      if (ref->used() && ref->input >= static_cast<int>(m.program.outputs.size()))
        fail(what, lobe + " refers to input " + std::to_string(ref->input) + ", which the material does not have");
    check_finite(l.weight, 0.0, what, lobe + " weight");
    check_finite(l.color, 0.0, what, lobe + " color");
    check_finite(l.tint, 0.0, what, lobe + " tint");
    if (!std::isfinite(l.roughness) || l.roughness < 0.0 || l.roughness > 1.0)
      fail(what, lobe + " roughness must be in [0, 1]");
    if (!std::isfinite(l.ior) || l.ior <= 0.0) fail(what, lobe + " ior must be a positive number");
    if (!(std::isfinite(l.stretch_x) && std::isfinite(l.stretch_y) && l.stretch_x > 0.0 && l.stretch_y > 0.0 &&
          l.stretch_x <= 1e3 && l.stretch_y <= 1e3))
      fail(what, lobe + " stretch must be two positive numbers up to 1000");
    if (!std::isfinite(l.rotation)) fail(what, lobe + " rotation must be a finite number");
    if (l.anisotropic() && l.kind != LobeKind::Conductor && l.kind != LobeKind::Glossy)
      fail(what, lobe + ": only conductor and glossy lobes can be anisotropic");
    if (l.layer && !((l.kind == LobeKind::Dielectric && l.parts == kReflection) || l.kind == LobeKind::MicrofiberSheen))
      fail(what, lobe + ": only a dielectric reflection or a microfiber sheen can be a layer");
    if (l.beckmann && !l.microfacet()) fail(what, lobe + ": only conductor, glossy and dielectric lobes are Beckmann");
    if (l.multiscatter && l.beckmann) fail(what, lobe + ": multiscatter is GGX's, not Beckmann's");
    if (l.multiscatter && l.kind == LobeKind::Dielectric && l.parts == kRefraction)
      fail(what, lobe + ": multiscatter is for conductor, glossy and dielectric lobes with reflection");
    prepare_lobe(l);
    double color_gain = 1.0;
    if (l.color_input.used()) {  // a colour the program cannot bound is kept within [0, 1]
      const int i = l.color_input.input;
      if (!std::isfinite(gain[i])) {
        m.program.output_max.resize(m.program.outputs.size(), std::numeric_limits<float>::infinity());
        m.program.output_max[i] = 1.0f;
        gain[i] = 1.0;
      }
      color_gain = gain[i];
    }
    bound += l.weight * (l.kind == LobeKind::Dielectric ? glm::max(l.color * color_gain, l.tint) : l.color * color_gain);
  }
  m.base_color = bound;
}

uint32_t Scene::add_material(Material m) {
  ensure_mutable();
  check_new_material(m);
  materials_.push_back(std::move(m));
  invalidate_lights();  // lights point into materials_ (textured emission); the BVH does not read them
  return static_cast<uint32_t>(materials_.size() - 1);
}

// The surfaces keep their BVH; what the material's emission lights is prepared again.
void Scene::replace_material(uint32_t index, Material m) {
  ensure_mutable();
  const std::string what = quoted("material", m.name);
  check_material(index, what);
  check_new_material(m);
  if (m.emits()) {
    for (const SphereInfo& s : spheres_)
      if (s.material == index) fail(what, "a sphere uses it, and spheres cannot emit");
    for (const RevolveSegment& r : revolve_segments_)
      if (r.material == index) fail(what, "a Bezier revolve uses it, and revolves cannot emit");
  }
  materials_[index] = std::move(m);
  invalidate_lights();
}

void Scene::check_new_material(Material& m) const {
  const std::string what = quoted("material", m.name);
  if (m.kind == MaterialKind::Mixture)
    check_lobes(m, what);
  else
    check_inputs(m, what);
  m.program.find_needs();
  check_finite(m.base_color, 0.0, what, "base_color");
  check_power(m.emission, what, "emission");
  check_finite(m.specular_tint, 0.0, what, "specular_tint");
  if (!std::isfinite(m.roughness) || m.roughness < 0.0 || m.roughness > 1.0)
    fail(what, "roughness must be in [0, 1]");
  if (!std::isfinite(m.ior) || m.ior <= 0.0) fail(what, "ior must be a positive number");
  if (m.texture >= static_cast<int>(textures_.size())) fail(what, "texture index out of range");
  if (m.medium < -1 || m.medium >= static_cast<int>(media_.size())) fail(what, "medium index out of range");
}

uint32_t Scene::add_texture(const std::string& name, Texture texture, bool clear_unusable) {
  ensure_mutable();
  const std::string what = quoted("texture", name);
  if (texture.unusable_texels() > 0 && !clear_unusable) {
    const UnusableTexel& t = texture.first_unusable();
    const std::string where = "pixel (x " + std::to_string(t.x) + ", y " + std::to_string(t.y) + ")";
    if (!std::isfinite(t.value)) fail(what, where + " has a NaN or Inf component");
    fail(what, where + " has a negative colour component " + number(t.value) + " (an albedo cannot be negative)");
  }
  textures_.push_back(std::move(texture));
  invalidate_lights();  // the world's environment points into textures_, which may have moved
  return static_cast<uint32_t>(textures_.size() - 1);
}

void Scene::check_material(uint32_t material, const std::string& what) const {
  if (material >= materials_.size())
    fail(what, "material index " + std::to_string(material) + " out of range (scene has " +
                   std::to_string(materials_.size()) + " materials)");
}

// Emission is sampled as light only on triangles; on a sphere or revolve it
// would glow without lighting anything, so refuse it rather than be wrong.
void Scene::check_not_emissive(uint32_t material, const std::string& what) const {
  if (materials_[material].emits())
    fail(what, "emissive material '" + materials_[material].name +
                   "' is supported on meshes only (use a sphere light, or tessellate)");
}

void Scene::add_sphere(const std::string& name, const Vec3& center, double radius, uint32_t material,
                       uint32_t object_id, uint8_t visibility) {
  ensure_mutable();
  const std::string what = quoted("sphere", name);
  check_coordinates(center, what, "center");
  if (!std::isfinite(radius) || radius <= 0.0) fail(what, "radius must be a positive number");
  check_size(radius, what, "radius");
  check_material(material, what);
  check_not_emissive(material, what);
  spheres_.push_back(SphereInfo{SpherePrim{center, radius}, material, object_id, visibility});
  geometry_changed(object_id);
}

void Scene::add_bezier_revolve(const std::string& name, const std::vector<Vec2>& points, bool cubic_chain,
                               const Mat4& object_to_world, uint32_t material, uint32_t object_id,
                               uint8_t visibility) {
  ensure_mutable();
  const std::string what = quoted("bezier revolve", name);
  check_material(material, what);
  check_not_emissive(material, what);
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
    revolve_segments_.push_back(RevolveSegment{index, static_cast<uint32_t>(s), material, object_id, visibility});
  geometry_changed(object_id);
}

void Scene::add_light(Light light) {
  ensure_mutable();
  const std::string what = quoted("light", light.name);
  check_power(light.power, what, "power");
  check_coordinates(light.position, what, "position");
  check_finite(light.direction, what, "direction");
  check_coordinates(light.axis_u, what, "size");
  check_coordinates(light.axis_v, what, "size");
  const bool needs_direction = light.kind == LightKind::Spot || light.kind == LightKind::Rectangle ||
                               light.kind == LightKind::Disk || light.kind == LightKind::Sun;
  if (needs_direction) {
    Vec3 d;
    if (!safe_normalize(light.direction, d)) fail(what, "direction must be non-zero");
    light.direction = d;
  }
  if (light.kind == LightKind::Sphere) {
    if (!(light.radius > 0.0 && std::isfinite(light.radius))) fail(what, "radius must be a positive number");
    check_size(light.radius, what, "radius");
  }
  if (light.kind == LightKind::Spot && light.radius > 0.0) check_size(light.radius, what, "radius");
  if (light.kind == LightKind::Rectangle || light.kind == LightKind::Disk) {
    const double su = max_abs(light.axis_u), sv = max_abs(light.axis_v);
    if (!(su > 0.0 && sv > 0.0)) fail(what, "size must be positive in both directions");
    check_size(2.0 * su, what, "size along x");
    check_size(2.0 * sv, what, "size along y");
    // Area (computed without underflow) at least kMinSize^2, so that the
    // radiance P / (pi A) stays finite: not a sliver.
    const double sine = glm::length(glm::cross(light.axis_u / su, light.axis_v / sv));
    if (!(sine > 0.0)) fail(what, "size must be positive in both directions (the light's axes are parallel)");
    if (!(4.0 * su * sv * sine >= kMinSize * kMinSize))
      fail(what, "size: the light's area is below " + number(kMinSize * kMinSize) + " m^2 (a sliver)");
  }
  if (light.kind == LightKind::Spot && !(light.cos_half_spot < 1.0 && light.cos_half_spot >= -1.0))
    fail(what, "spot angle must be in (0, 2*pi], and large enough that its cosine differs from 1");
  if (light.kind == LightKind::Spot && !(light.spot_smooth >= 0.0)) fail(what, "spot blend must be >= 0");
  if (light.kind == LightKind::Sun && !(light.cos_sun > -1.0 && light.cos_sun <= 1.0))
    fail(what, "sun angle must be in [0, pi]");
  if (!(light.spread > 1e-6 && light.spread <= kPi)) fail(what, "spread must be in (1e-6, pi]");
  check_max_bounces(light.max_bounces, what);
  if (light.kind == LightKind::Background || light.kind == LightKind::Triangle)
    fail(what, "use set_background or an emissive material for this kind");
  user_lights_.push_back(light);
  invalidate_lights();
}

void Scene::set_camera(const Camera& c) {
  ensure_mutable();
  const std::string what = "camera";
  if (c.width <= 0 || c.height <= 0) fail(what, "width and height must be positive");
  if (static_cast<double>(c.width) * c.height > 1e9) fail(what, "resolution too large");
  for (int i = 0; i < 4; ++i) check_finite(Vec3(c.camera_to_world[i]), what, "matrix");
  check_coordinates(c.position(), what, "position (matrix translation)");
  if (c.projection == Projection::Perspective && !(c.fov > 0.0 && c.fov < kPi))
    fail(what, "fov must be in (0, pi) radians");
  if (c.projection == Projection::Orthographic && !(c.ortho_scale > 0.0 && std::isfinite(c.ortho_scale)))
    fail(what, "ortho_scale must be a positive number");
  if (c.projection == Projection::Orthographic) check_size(c.ortho_scale, what, "ortho_scale");
  if (!std::isfinite(c.shift_x) || !std::isfinite(c.shift_y)) fail(what, "shift is not finite");
  if (c.frame_width < 0 || c.frame_height < 0) fail(what, "frame width and height must be >= 0");
  if (std::fabs(c.shift_x) > 1e3 || std::fabs(c.shift_y) > 1e3)
    fail(what, "shift must be within +-1000 image widths (Blender allows +-10)");
  if (!(c.clip_start >= 0.0) || !(c.clip_end > c.clip_start)) fail(what, "need 0 <= clip_start < clip_end");
  if (c.clip_start > kMaxCoordinate) fail(what, "clip_start is above the supported " + number(kMaxCoordinate) + " m");
  if (!(c.focus_distance > 0.0) || !std::isfinite(c.focus_distance)) fail(what, "focus_distance must be positive");
  if (c.focus_distance > kMaxCoordinate || c.focus_distance < kMinSize)
    fail(what, "focus_distance is outside the supported range [" + number(kMinSize) + ", " + number(kMaxCoordinate) + "] m");
  if (!(c.aperture_radius >= 0.0) || !std::isfinite(c.aperture_radius)) fail(what, "aperture_radius must be >= 0");
  if (c.aperture_radius > kMaxCoordinate) fail(what, "aperture_radius is above the supported " + number(kMaxCoordinate) + " m");
  if (!(c.focal_length >= 0.0) || !std::isfinite(c.focal_length)) fail(what, "focal_length must be >= 0");
  if (c.focal_length > kMaxCoordinate) fail(what, "focal_length is above the supported " + number(kMaxCoordinate) + " m");
  // Orthonormalise: a scaled camera object must not skew the rays. Normalised
  // before the cross product, so that huge or tiny scales neither overflow nor underflow.
  Camera cam = c;
  Vec3 z, x;
  if (!safe_normalize(Vec3(c.camera_to_world[2]), z) || !safe_normalize(Vec3(c.camera_to_world[1]), x) ||
      !safe_normalize(glm::cross(x, z), x))
    fail(what, "matrix is singular");
  const Vec3 y = glm::cross(z, x);
  cam.camera_to_world[0] = glm::dvec4(x, 0.0);
  cam.camera_to_world[1] = glm::dvec4(y, 0.0);
  cam.camera_to_world[2] = glm::dvec4(z, 0.0);
  camera_ = cam;
  has_camera_ = true;
  camera_media_placed_ = false;
}

void Scene::set_background(const Color& radiance, uint8_t visibility, int max_bounces) {
  ensure_mutable();
  check_power(radiance, "background", "radiance");
  check_max_bounces(max_bounces, "background");
  background_ = radiance;
  environment_input_.reset();
  camera_environment_input_.reset();
  background_visibility_ = visibility;
  background_max_bounces_ = max_bounces;
  invalidate_lights();
}

void Scene::set_environment(uint32_t texture, const Mat4& world_to_texture, const Color& strength,
                            EnvironmentProjection projection, uint8_t visibility, int max_bounces) {
  ensure_mutable();
  const std::string what = "environment";
  check_max_bounces(max_bounces, what);
  if (texture >= textures_.size()) fail(what, "texture index out of range");
  check_power(strength, what, "strength");
  const Mat3 rotation(world_to_texture);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double dot = glm::dot(rotation[i], rotation[j]);
      if (!(std::fabs(dot - (i == j ? 1.0 : 0.0)) < 1e-6))
        fail(what, "world_to_texture must be a rotation (orthonormal columns)");
    }
  if (!(glm::determinant(rotation) > 0.0)) fail(what, "world_to_texture must be a rotation, not a reflection");
  environment_input_ = std::make_unique<EnvironmentInput>(EnvironmentInput{texture, rotation, strength, projection});
  camera_environment_input_.reset();
  background_ = Color(0.0);
  background_visibility_ = visibility;
  background_max_bounces_ = max_bounces;
  invalidate_lights();
}

void Scene::set_camera_background(uint32_t texture, const Color& strength) {
  ensure_mutable();
  const std::string what = "camera background";
  if (texture >= textures_.size()) fail(what, "texture index out of range");
  check_power(strength, what, "strength");
  camera_environment_input_ = std::make_unique<EnvironmentInput>(
      EnvironmentInput{texture, Mat3(1.0), strength, EnvironmentProjection::Equirectangular});
  invalidate_lights();
}

// A built scene keeps its triangles' vertex indices in the BVH's leaf records only (12 bytes a
// triangle less); they come back in triangle order before the scene changes or is built again.
void Scene::restore_triangles() {
  std::vector<TriangleVertices>& triangles = meshes_.triangles;
  if (triangles.size() == meshes_.info.size()) return;
  triangles.resize(meshes_.info.size());
  for (size_t i = 0; i < triangles.size(); ++i) triangles[i] = leaf_prims_[slot_of_triangle_[i]].vertices;
}

const TriangleVertices& Scene::triangle_vertices(uint32_t triangle) const {
  const std::vector<TriangleVertices>& triangles = meshes_.triangles;
  return triangles.size() == meshes_.info.size() ? triangles[triangle] : leaf_prims_[slot_of_triangle_[triangle]].vertices;
}

// After the build: the triangles are found through their leaf slots. What the build freed (the
// triangle-ordered copy, the build's boxes and node lists, some in the arenas of the threads that
// built subtrees) goes back to the system: glibc keeps freed memory resident otherwise, 70 bytes a
// triangle of a 10^6-triangle mesh.
void Scene::release_triangles() {
  slot_of_triangle_.resize(meshes_.triangles.size());
  for (uint32_t slot = 0; slot < leaf_prims_.size(); ++slot)
    if (leaf_prims_[slot].kind == PrimitiveKind::Triangle) slot_of_triangle_[leaf_prims_[slot].index] = slot;
  std::vector<TriangleVertices>().swap(meshes_.triangles);
  meshes_.shrink_to_fit();
  return_freed_memory();
}

void Scene::build() {
  if (!geometry_built_ || !changed_objects_.empty()) {
    build_geometry();
    lights_built_ = false;
  } else if (!moved_objects_.empty()) {
    refit_moved_objects();
    lights_built_ = false;
  }
  if (!lights_built_) {
    prepare_media();
    prepare_lights();
    camera_media_placed_ = false;  // the geometry or the media changed
  }
  if (!camera_media_placed_) place_camera_in_media();
  camera_media_placed_ = true;  // a built scene unchanged: build() writes nothing a render reads
}

void Scene::build_geometry() {
  restore_triangles();
  const std::vector<TriangleVertices>& triangles = meshes_.triangles;
  const auto box_of = [&](size_t i) { return primitive_box(prim_ref(static_cast<uint32_t>(i))); };
  if (dynamic_) {
    std::vector<Aabb> boxes(primitive_count());
    for (size_t i = 0; i < boxes.size(); ++i) boxes[i] = box_of(i);
    build_object_bvh(boxes, geometry_built_);
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
  finish_geometry();
  release_triangles();
  geometry_built_ = true;
}

bool Scene::copies_triangles() const {
  return layout_ == GeometryLayout::Copies ||
         (layout_ == GeometryLayout::Auto && meshes_.triangle_count() <= kCopiedTrianglesMax);
}

// Written on every thread, the page faults too (huge pages: the kernel's compaction to find them):
// 960 MB of copies at 10^7 triangles took 1.5-2.1 s to resize on one thread.
void Scene::copy_leaf_triangles() {
  copied_leaves_.resize(leaf_prims_.size());  // unwritten (HugePageFillVector)
  parallel_for(hardware_threads(), leaf_prims_.size(), [&](size_t begin, size_t end) {
    for (size_t slot = begin; slot < end; ++slot) {
      const LeafPrim& p = leaf_prims_[slot];
      copied_leaves_[slot] =
          CopiedLeaf{p.kind == PrimitiveKind::Triangle ? meshes_.triangle(p.vertices) : TrianglePrim{}, p};
    }
  });
}

void Scene::set_geometry_layout(GeometryLayout layout) {
  ensure_mutable();
  if (layout == layout_) return;
  restore_triangles();
  layout_ = layout;
  invalidate();
}

// Each mesh's vertices in the order the BVH leaves first name them, so that a leaf's triangles find
// their vertices side by side (in the input's order they may lie anywhere in the mesh: random rays
// through a 1.3 x 10^6-triangle grid and soup traced about 15% slower so, in the Compact layout). A
// dynamic scene keeps the input's order, which replace_mesh writes in place.
void Scene::order_vertices_by_leaf() {
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
void Scene::build_object_bvh(const std::vector<Aabb>& boxes, bool reuse_unchanged) {
  std::unordered_map<uint32_t, uint32_t> previous;
  previous.swap(object_group_);
  std::vector<uint32_t> group(boxes.size());
  for (uint32_t i = 0; i < group.size(); ++i) {
    const PrimRef ref = prim_ref(i);
    const uint32_t object = ref.kind == PrimitiveKind::Triangle ? meshes_.meshes[meshes_.info[ref.index].mesh].object
                            : ref.kind == PrimitiveKind::Sphere ? spheres_[ref.index].object
                                                                : revolve_segments_[ref.index].object;
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
void Scene::refit_moved_objects() {
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
  finish_geometry();
  moved_objects_.clear();
  subtrees_built_ = 0;
}

void Scene::finish_geometry() {
  const size_t leaves = copied_leaves_.empty()
                            ? leaf_prims_.size() * sizeof(LeafPrim) + meshes_.vertices.size() * sizeof(Vec3)
                            : copied_leaves_.size() * sizeof(CopiedLeaf);
  interleave_ = bvh_.nodes().size() * sizeof(BvhNode) + leaves > kInterleaveBytes;  // what a walk reads
  const Aabb bounds = bvh_.bounds();
  offset_floor_ = bounds.empty() ? 1e-12 : 1e-10 * max_abs(bounds.extent()) + 1e-300;
}

void Scene::set_dynamic(bool dynamic) {
  ensure_mutable();
  if (dynamic == dynamic_) return;
  restore_triangles();
  dynamic_ = dynamic;
  invalidate();
}

// The user lights, the world, the emissive triangles (read from their leaf records) and the
// emitting media's regions.
void Scene::prepare_lights() {
  lights_.clear();
  Aabb light_bounds = bvh_.bounds();
  for (const Light& l : user_lights_)
    if (l.kind != LightKind::Sun) light_bounds.grow(l.position);
  for (Light l : user_lights_) {
    prepare_light(l, light_bounds);
    lights_.push_back(l);
  }
  environment_.reset();
  if (environment_input_ && max_component(environment_input_->strength) > 0.0) {
    const EnvironmentInput& e = *environment_input_;
    environment_ = std::make_unique<Environment>(&textures_[e.texture], e.world_to_texture, e.strength, e.projection);
  }
  camera_environment_.reset();
  if (const EnvironmentInput* e = camera_environment_input_.get())
    camera_environment_ = std::make_unique<Environment>(&textures_[e->texture], e->world_to_texture, e->strength,
                                                        e->projection);
  if (max_component(background_) > 0.0 || environment_) {
    Light l;
    l.kind = LightKind::Background;
    l.name = "background";
    l.power = background_;
    l.environment = environment_.get();
    l.visibility = background_visibility_;
    l.max_bounces = background_max_bounces_;
    prepare_light(l, light_bounds);
    lights_.push_back(l);
  }
  for (uint32_t i = 0; i < meshes_.triangle_count(); ++i) {
    const Material& m = materials_[meshes_.info[i].material];
    if (!m.emits()) continue;
    const TrianglePrim triangle = this->triangle(i);
    if (triangle_area(triangle) <= 0.0) continue;
    Light l;
    l.kind = LightKind::Triangle;
    l.name = m.name;
    l.triangle = triangle;
    l.primitive = i;
    l.radiance = m.emission;
    if (m.emission_input >= 0) textured_emission(m, i, l);
    prepare_light(l, light_bounds);
    lights_.push_back(l);
  }
  prepare_medium_lights(light_bounds);
  place_lights_in_media();
  lights_built_ = true;
}

// A triangle's textured emission: its material's program and UVs, and as its radiance (which its
// power and the light sampler go by) the mean over the triangle of kSide^2 stratified values.
// Photons and light samples take the emission where they start, so any positive estimate keeps them
// unbiased; a floor keeps bright detail between the samples from never being chosen.
void Scene::textured_emission(const Material& m, uint32_t triangle, Light& l) const {
  const MeshRecord& mesh = meshes_.meshes[meshes_.info[triangle].mesh];
  const TriangleVertices& v = triangle_vertices(triangle);
  l.program = &m.program;
  l.program_output = m.emission_input;
  l.textures = &textures_;
  l.object = &object_info(mesh.object);
  l.emission = m.emission;
  for (int k = 0; k < 3; ++k)
    l.uvs[k] = mesh.uvs.present() ? Vec2(meshes_.corner(meshes_.uvs, mesh.uvs, mesh, triangle, v.v[k], k)) : Vec2(0.0);
  constexpr int kSide = 4;
  Color sum(0.0), most(0.0);
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j) {
      const Color here = radiance_at(l, sample_uniform_triangle((i + 0.5) / kSide, (j + 0.5) / kSide));
      sum += here;
      most = glm::max(most, here);
    }
  const double bound = m.program.output_bound(m.emission_input, textures_);
  const Color brightest = std::isfinite(bound) ? m.emission * bound : most;
  constexpr double kFloor = 1e-2;  // of the brightest the program can make it
  l.radiance = glm::max(sum / double(kSide * kSide), kFloor * brightest);
}

Color Scene::emission(const Hit& hit, const Vec3& wo, const LightPath& path) const {
  const Material& m = materials_[hit.material];
  if (m.emission_input < 0) return m.emission;
  std::array<Vec3f, kMaxInputs> values;
  m.program.run(shading_context(hit, wo, 0.0, path), textures_, values.data());
  return m.emission * Color(values[m.emission_input]);
}

void Scene::check_energy_range(int max_bounces) const {
  for (const Light& l : lights_)
    if (!std::isfinite(max_component(l.flux)))
      fail(quoted("light", l.name), "its emitted flux overflows (the scene is too large for its power)");
  // A photon's share is scaled at each scattering by weight / survival, at most
  // the largest colour component above 1: it stays below gain^bounces.
  double gain = 1.0;
  const Material* greedy = nullptr;
  for (const Material& m : materials_) {
    if (m.kind == MaterialKind::Metal || is_black(m)) continue;  // metal Fresnel is clamped to 1
    double g = max_component(m.base_color);
    if (m.texture >= 0 && m.kind != MaterialKind::Glass) g *= textures_[m.texture].max_rgb();
    if (g > gain) gain = g, greedy = &m;
  }
  if (greedy == nullptr) return;
  const double log_growth = std::max(1, max_bounces) * std::log10(gain);
  if (log_growth > std::log10(kMaxPhotonGain))
    throw std::invalid_argument(
        "material '" + greedy->name + "': its colour " + number(gain) +
        " reflects more light than it receives; over max_bounces=" + std::to_string(max_bounces) +
        " scatterings a photon's flux could grow by 1e" + std::to_string(static_cast<int>(log_growth)) +
        ", above the supported " + number(kMaxPhotonGain) + " (keep colours <= 1 or lower max_bounces)");
}

// Triangles, by far the most common, are tested inline; the rest out of line.
bool Scene::is_holdout(const Hit& hit) const {
  uint32_t id = hit.primitive;
  if (id < meshes_.triangle_count()) return meshes_.meshes[meshes_.info[id].mesh].visibility & kHoldoutFlag;
  id -= meshes_.triangle_count();
  if (id < spheres_.size()) return spheres_[id].visibility & kHoldoutFlag;
  id -= static_cast<uint32_t>(spheres_.size());
  return id < revolve_segments_.size() && (revolve_segments_[id].visibility & kHoldoutFlag);
}

// Primitive i of a build: the triangles in order, then the spheres, then the revolve segments.
Scene::PrimRef Scene::prim_ref(uint32_t i) const {
  const uint32_t triangles = static_cast<uint32_t>(meshes_.info.size());
  const uint32_t spheres = static_cast<uint32_t>(spheres_.size());
  if (i < triangles) return {PrimitiveKind::Triangle, i};
  if (i < triangles + spheres) return {PrimitiveKind::Sphere, i - triangles};
  return {PrimitiveKind::BezierRevolve, i - triangles - spheres};
}

Aabb Scene::primitive_box(const PrimRef& ref) const {
  switch (ref.kind) {
    case PrimitiveKind::Triangle: return triangle_box(meshes_.triangle(meshes_.triangles[ref.index]));
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

uint8_t Scene::visibility_of(const PrimRef& ref) const {
  switch (ref.kind) {
    case PrimitiveKind::Triangle: return meshes_.meshes[meshes_.info[ref.index].mesh].visibility;
    case PrimitiveKind::Sphere: return spheres_[ref.index].visibility;
    default: return revolve_segments_[ref.index].visibility;
  }
}

inline bool Scene::intersect_slot(uint32_t slot, const Ray& ray, double& tmax, Hit& scratch) const {
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

inline bool Scene::record_triangle_hit(uint32_t slot, uint32_t triangle, const TrianglePrim& tri, const Ray& ray,
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

bool Scene::intersect_non_triangle(uint32_t slot, const Ray& ray, double& tmax, Hit& scratch) const {
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

size_t Scene::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  size_t b = meshes_.memory_bytes() + bytes(copied_leaves_) + bytes(spheres_) + bytes(revolve_segments_) +
             bytes(slot_of_triangle_) + bytes(leaf_prims_) + bytes(bvh_.nodes()) + bytes(bvh_.prim_order()) +
             bytes(materials_) + bytes(lights_) + bytes(user_lights_) + bytes(objects_);
  if (object_bvh_) b += object_bvh_->memory_bytes();
  for (const Texture& t : textures_) b += sizeof(Texture) + t.memory_bytes();
  for (const auto& g : grids_) b += sizeof(VoxelGrid) + g->memory_bytes();
  return b;
}

bool Scene::intersect(const Ray& ray, Hit& hit, double tmax) const {
  Hit scratch;
  bvh_.closest(
      ray.origin, ray.direction, tmax, [&](uint32_t slot, double& t) { return intersect_slot(slot, ray, t, scratch); },
      [&](uint32_t first, uint32_t count) { prefetch_leaf(first, count); });
  if (!scratch.found()) return false;
  hit = scratch;
  fill_hit(ray, hit, scratch.uv.x, scratch.uv.y);
  return true;
}

void Scene::intersect_many(const Ray* rays, size_t count, Hit* hits) const {
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

bool Scene::occluded(const Ray& ray, double distance) const {
  Hit scratch;
  return bvh_.any(ray.origin, ray.direction, distance,
                  [&](uint32_t slot, double& t) { return intersect_slot(slot, ray, t, scratch); });
}

// `hit.primitive` holds the leaf slot on entry and the primitive id on return.
void Scene::fill_hit(const Ray& ray, Hit& hit, double b1, double b2) const {
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
      const uint32_t* v = ref.vertices.v;
      const double b0 = 1.0 - b1 - b2;
      auto corners = [&](const auto& values, const AttributeRange& range) {
        using T = std::decay_t<decltype(values[0])>;
        std::array<T, 3> out;
        for (int k = 0; k < 3; ++k) out[k] = meshes_.corner(values, range, mesh, ref.index, v[k], k);
        return out;
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

namespace {

// The shading normal a normal map gives (see NormalMap), kept in front of the geometric normal.
// A Direct normal faces the viewer (as Blender's nodes see the surface); `backfacing` turns it to
// the primitive's side, where SurfacePoint keeps its normals.
Vec3 mapped_normal(const NormalMap& map, const SurfacePoint& sp, const glm::vec4& tangent, bool backfacing) {
  const Vec3 c = map.space == NormalMap::Direct ? Vec3(sp.inputs[map.input]) : 2.0 * Vec3(sp.inputs[map.input]) - 1.0;
  Vec3 n;
  if (map.space == NormalMap::Direct) {
    n = backfacing ? -c : c;
  } else if (map.space == NormalMap::World) {
    n = c;
  } else {
    if (tangent.w == 0.0f) return sp.ns;  // no tangents (not a mesh with a UV map): as Cycles, unmapped
    const Vec3 t(tangent), b = static_cast<double>(tangent.w) * glm::cross(sp.ns, t);
    n = c.x * t + c.y * b + c.z * sp.ns;
  }
  // Cycles blends a tangent-space normal with the surface's before normalising it, others after.
  if (map.space != NormalMap::Tangent && !safe_normalize(n, n)) return sp.ns;
  if (map.strength != 1.0) n = sp.ns + (n - sp.ns) * std::max(map.strength, 0.0);
  if (!safe_normalize(n, n)) return sp.ns;
  // A normal turned away from the geometric one would let light through an opaque surface.
  constexpr double kMinCos = 0.01;
  const double cos_g = glm::dot(n, sp.ng);
  if (cos_g < kMinCos && !safe_normalize(n + (kMinCos - cos_g) * sp.ng, n)) return sp.ns;
  return n;
}

// Where Blender's nodes see a surface point: normals turned to the viewer, as Cycles turns them.
ShadingContext context_at(const Vec3& position, const Vec3& ng, const Vec3& ns, const Vec3& wo, const Vec2& uv,
                          const glm::vec4& tangent) {
  ShadingContext c;
  c.position = position;
  c.backfacing = glm::dot(wo, ng) < 0.0;
  const double side = c.backfacing ? -1.0 : 1.0;
  c.normal = side * ns;
  c.true_normal = side * ng;
  c.incoming = wo;
  c.uv = uv;
  if (tangent.w != 0.0f) {
    c.tangent = Vec3(tangent);
    c.tangent_sign = tangent.w;
  }
  return c;
}

}  // namespace

const ObjectInfo& Scene::object_info(uint32_t object) const {
  static const ObjectInfo kNone;
  if (object == kWorldObject) return world_object_;
  return object < objects_.size() ? objects_[object] : kNone;
}

uint32_t Scene::add_grid(std::shared_ptr<const VoxelGrid> grid) {
  ensure_mutable();
  grids_.push_back(std::move(grid));
  return static_cast<uint32_t>(grids_.size() - 1);
}

std::shared_ptr<const VoxelGrid> Scene::grid(uint32_t index) const {
  if (index >= grids_.size()) throw std::out_of_range("grid " + std::to_string(index) + " does not exist");
  return grids_[index];
}

void Scene::set_object_info(uint32_t object, const ObjectInfo& info) {
  ensure_mutable();
  if (object >= kMaxObjectId) fail("object " + std::to_string(object), "object ids for node programs go up to " +
                                                                            std::to_string(kMaxObjectId - 1));
  invalidate_lights();  // a textured emission's light points into objects_; the BVH does not read it
  if (object == kWorldObject) {
    world_object_ = info;
    return;
  }
  if (objects_.size() <= object) objects_.resize(size_t(object) + 1);
  objects_[object] = info;
}

ShadingContext Scene::shading_context(const Hit& hit, const Vec3& wo, double footprint,
                                      const LightPath& path) const {
  ShadingContext c = context_at(hit.position, hit.geometric_normal, hit.shading_normal, wo, hit.uv, hit.tangent);
  c.footprint = footprint;
  c.path = path;
  c.object = &object_info(hit.object);
  c.camera = has_camera_ ? &camera_ : nullptr;
  add_primitive_data(materials_[hit.material], hit.primitive, hit.position, c);
  return c;
}

void Scene::add_primitive_data(const Material& m, uint32_t primitive, const Vec3& position, ShadingContext& c) const {
  if (primitive >= meshes_.triangle_count()) return;  // primitive ids number the triangles first
  const NodeProgram::Needs needs = m.program.needs();
  if (!needs.uv_gradients && !needs.attribute) return;
  const MeshRecord& mesh = meshes_.meshes[meshes_.info[primitive].mesh];
  const TriangleVertices& v = triangle_vertices(primitive);
  const TrianglePrim t = meshes_.triangle(v);
  auto corners = [&](const auto& values, const AttributeRange& range) {
    using T = std::decay_t<decltype(values[0])>;
    std::array<T, 3> out;
    for (int k = 0; k < 3; ++k) out[k] = meshes_.corner(values, range, mesh, primitive, v.v[k], k);
    return out;
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

// How u and v change along a triangle: the gradients whose dot products with its edges give the
// UV differences along them (and zero along the normal).
void Scene::uv_gradients(const TrianglePrim& t, const glm::vec2* uv, Vec3& du, Vec3& dv) {
  const Vec3 n = glm::cross(t.e1, t.e2);
  const double det = glm::dot(n, n);
  if (!(det > 0.0)) return;
  const Vec3 b1 = glm::cross(t.e2, n) / det, b2 = glm::cross(n, t.e1) / det;
  const Vec2 d1 = Vec2(uv[1] - uv[0]), d2 = Vec2(uv[2] - uv[0]);
  du = d1.x * b1 + d2.x * b2;
  dv = d1.y * b1 + d2.y * b2;
}

SurfacePoint Scene::surface_point(const Hit& hit, const Vec3& wo, double footprint, const LightPath& path) const {
  const Material& m = materials_[hit.material];
  SurfacePoint sp;
  sp.ng = hit.geometric_normal;
  sp.ns = hit.shading_normal;
  sp.tangent = hit.tangent.w != 0.0f ? Vec3(hit.tangent) : Vec3(0.0);
  sp.softening = m.normal_map.softening;
  if (m.kind != MaterialKind::Mixture) {
    sp.albedo = m.texture >= 0 ? textures_[m.texture].lookup(hit.uv) * m.base_color : m.base_color;
    return sp;
  }
  sp.albedo = m.base_color;
  if (m.program.empty()) return sp;
  const ShadingContext c = shading_context(hit, wo, footprint, path);
  m.program.run(c, textures_, sp.inputs.data());
  if (m.normal_map.input >= 0) {
    sp.smooth_normal = sp.ns;
    sp.ns = mapped_normal(m.normal_map, sp, hit.tangent, c.backfacing);
    if (m.normal_map.valid_reflection) {
      const double side = c.backfacing ? -1.0 : 1.0;
      sp.ns = side * valid_reflection(side * sp.ng, wo, side * sp.ns);
    }
  }
  return sp;
}

SurfacePoint Scene::surface_point(const SurfaceRecord& r) const {
  const Material& m = materials_[r.material];
  SurfacePoint sp;
  sp.ng = r.ng;
  sp.ns = r.ns;
  sp.smooth_normal = Vec3(r.smooth_normal);
  sp.tangent = Vec3(r.tangent);
  sp.softening = m.normal_map.softening;
  if (m.kind != MaterialKind::Mixture) {
    sp.albedo = m.texture >= 0 ? textures_[m.texture].lookup(Vec2(r.uv)) * m.base_color : m.base_color;
    return sp;
  }
  sp.albedo = m.base_color;
  if (m.program.empty()) return sp;
  // The program sees the normal before the normal map, as it did where the hit point was made.
  const Vec3 unmapped = r.smooth_normal != Vec3f(0.0f) ? Vec3(r.smooth_normal) : r.ns;
  ShadingContext c = context_at(r.position, r.ng, unmapped, r.wo, Vec2(r.uv), r.tangent);
  c.object = &object_info(r.object);
  c.camera = has_camera_ ? &camera_ : nullptr;
  c.path = r.path;
  add_primitive_data(m, r.primitive, r.position, c);
  m.program.run(c, textures_, sp.inputs.data());
  return sp;
}

}  // namespace ppm
