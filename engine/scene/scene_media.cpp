// Participating media of the scene: the builders and the shadow rays through media (see
// scene/medium.h and Scene's media section).
#include "scene/input_checks.h"
#include "scene/scene.h"

#include <limits>

namespace ppm {
using namespace scene_input;

namespace {

// A coefficient per metre: finite, >= 0 (check_finite) and at most kMaxCoefficient (an opaque
// medium; the free-path samplers clamp there too).
void check_coefficient(const Color& c, const std::string& what, const std::string& field) {
  check_finite(c, 0.0, what, field);
  if (max_component(c) > kMaxCoefficient)
    fail(what, field + " " + number(max_component(c)) + " is above the supported " + number(kMaxCoefficient) +
                   " per metre");
}

}  // namespace

uint32_t Scene::add_medium(Medium m) {
  ensure_mutable();
  const std::string what = quoted("medium", m.name);
  check_coefficient(m.c.sigma_a, what, "sigma_a");
  check_coefficient(m.c.sigma_s, what, "sigma_s");
  check_power(m.c.emission, what, "emission");
  if (media_.size() >= static_cast<size_t>(std::numeric_limits<int16_t>::max()))
    fail(what, "a scene takes at most 32767 media");
  m.sigma_t = m.c.sigma_t();
  media_.push_back(std::move(m));
  return static_cast<uint32_t>(media_.size() - 1);
}

void Scene::set_world_medium(int medium) {
  ensure_mutable();
  if (medium < -1 || medium >= static_cast<int>(media_.size()))
    fail("world", "medium index " + std::to_string(medium) + " out of range (scene has " +
                      std::to_string(media_.size()) + " media)");
  world_medium_ = medium;
}

void Scene::set_material_medium(uint32_t material, int medium, bool surface) {
  ensure_mutable();
  check_material(material, "material " + std::to_string(material));
  const std::string what = quoted("material", materials_[material].name);
  if (medium < -1 || medium >= static_cast<int>(media_.size()))
    fail(what, "medium index " + std::to_string(medium) + " out of range (scene has " +
                   std::to_string(media_.size()) + " media)");
  if (!surface && materials_[material].emits())
    fail(what, "a boundary without a surface cannot emit (give the medium emission instead)");
  materials_[material].medium = medium;
  materials_[material].surface = surface;
  invalidate_lights();
}

bool Scene::has_media() const {
  if (world_medium_ >= 0) return true;
  for (const Material& m : materials_)
    if (m.medium >= 0 || !m.surface) return true;
  return false;
}

Color Scene::shadow_transmittance(const Ray& shadow, double distance, MediumStack stack) const {
  Color tr(1.0);
  Ray ray = shadow;
  for (int crossing = 0; crossing <= kMaxMediumCrossings; ++crossing) {
    Hit hit;
    const bool found = intersect(ray, hit, distance);
    if (const Medium* m = medium_of(stack)) tr *= transmittance(m->sigma_t, found ? hit.t : distance);
    if (!found) return tr;
    if (materials_[hit.material].surface) return Color(0.0);
    if (!(max_component(tr) > 0.0)) return Color(0.0);
    cross(hit, ray.direction, stack);
    distance -= hit.t;
    ray.origin = offset_point(hit.position, hit.geometric_normal, ray.direction, offset_floor_);
    if (!(distance > 0.0)) return tr;
  }
  return Color(0.0);
}

}  // namespace ppm
