// Scene building, validation and ray queries (see scene.h).
#include "scene/scene.h"

#include "math/sampling.h"
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
    if (geometry_.spheres_use(index)) fail(what, "a sphere uses it, and spheres cannot emit");
    if (geometry_.revolves_use(index)) fail(what, "a Bezier revolve uses it, and revolves cannot emit");
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

void Scene::add_mesh(const MeshInput& mesh) {
  ensure_mutable();
  const std::string what = quoted("mesh", mesh.name);
  for (uint32_t m : mesh.materials) check_material(m, what);
  geometry_.add_mesh(mesh, what);
  invalidate_lights();
}

void Scene::replace_mesh(const MeshInput& mesh) {
  ensure_mutable();
  const std::string what = quoted("mesh", mesh.name);
  for (uint32_t m : mesh.materials) check_material(m, what);
  geometry_.replace_mesh(mesh, what);
  invalidate_lights();
}

size_t Scene::remove_object(uint32_t object) {
  ensure_mutable();
  const size_t removed = geometry_.remove_object(object);
  if (removed > 0) invalidate_lights();
  return removed;
}

void Scene::set_dynamic(bool dynamic) {
  ensure_mutable();
  if (geometry_.set_dynamic(dynamic)) invalidate_lights();
}

void Scene::set_geometry_layout(GeometryLayout layout) {
  ensure_mutable();
  if (geometry_.set_layout(layout)) invalidate_lights();
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
  geometry_.add_sphere(SpherePrim{center, radius}, material, object_id, visibility);
  invalidate_lights();
}

void Scene::add_bezier_revolve(const std::string& name, const std::vector<Vec2>& points, bool cubic_chain,
                               const Mat4& object_to_world, uint32_t material, uint32_t object_id,
                               uint8_t visibility) {
  ensure_mutable();
  const std::string what = quoted("bezier revolve", name);
  check_material(material, what);
  check_not_emissive(material, what);
  geometry_.add_revolve(points, cubic_chain, object_to_world, material, object_id, visibility, what);
  invalidate_lights();
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

void Scene::build() {
  if (geometry_.build()) lights_built_ = false;
  if (!lights_built_) {
    prepare_media();
    prepare_lights();
    camera_media_placed_ = false;  // the geometry or the media changed
  }
  if (!camera_media_placed_) place_camera_in_media();
  camera_media_placed_ = true;  // a built scene unchanged: build() writes nothing a render reads
}

// The user lights, the world, the emissive triangles (read from their leaf records) and the
// emitting media's regions.
void Scene::prepare_lights() {
  lights_.clear();
  Aabb light_bounds = geometry_.bounds();
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
  for (uint32_t i = 0; i < geometry_.triangle_count(); ++i) {
    const Material& m = materials_[geometry_.triangle_material(i)];
    if (!m.emits()) continue;
    const TrianglePrim triangle = geometry_.triangle(i);
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
  l.program = &m.program;
  l.program_output = m.emission_input;
  l.textures = &textures_;
  l.object = &object_info(geometry_.triangle_object(triangle));
  l.emission = m.emission;
  const std::array<Vec2, 3> uvs = geometry_.triangle_uvs(triangle);
  for (int k = 0; k < 3; ++k) l.uvs[k] = uvs[k];
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

size_t Scene::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  size_t b = geometry_.memory_bytes() + bytes(materials_) + bytes(lights_) + bytes(user_lights_) + bytes(objects_);
  for (const Texture& t : textures_) b += sizeof(Texture) + t.memory_bytes();
  for (const auto& g : grids_) b += sizeof(VoxelGrid) + g->memory_bytes();
  return b;
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
  geometry_.add_primitive_data(materials_[hit.material].program.needs(), hit.primitive, hit.position, c);
  return c;
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
  geometry_.add_primitive_data(m.program.needs(), r.primitive, r.position, c);
  m.program.run(c, textures_, sp.inputs.data());
  return sp;
}

}  // namespace ppm
