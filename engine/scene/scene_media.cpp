// Participating media of the scene: the builders and the shadow rays through media (see
// scene/medium.h and Scene's media section).
#include "geometry/bezier_revolve.h"
#include "scene/input_checks.h"
#include "scene/scene.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <utility>
#include <vector>

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

// A medium's field (MediumField): its program valid for the scene's textures, terms that are
// coefficients and read one of its outputs.
void check_field(const MediumField& f, size_t textures, const std::string& what) {
  f.program.validate(textures, what);
  if (f.program.outputs.size() > kMaxFieldOutputs)
    fail(what, "a medium's program gives at most " + std::to_string(kMaxFieldOutputs) + " outputs");
  if (f.terms.empty()) fail(what, "a program needs terms that it scales");
  for (size_t k = 0; k < f.terms.size(); ++k) {
    const MediumTerm& t = f.terms[k];
    const std::string term = "terms[" + std::to_string(k) + "].";
    check_coefficient(t.sigma_a, what, term + "sigma_a");
    check_coefficient(t.sigma_s, what, term + "sigma_s");
    check_power(t.emission, what, term + "emission");
    if (t.input >= f.program.outputs.size())
      fail(what, term + "input " + std::to_string(t.input) + " is not one of the program's " +
                     std::to_string(f.program.outputs.size()) + " outputs");
  }
}

}  // namespace

uint32_t Scene::add_medium(Medium m) {
  ensure_mutable();
  const std::string what = quoted("medium", m.name);
  check_coefficient(m.c.sigma_a, what, "sigma_a");
  check_coefficient(m.c.sigma_s, what, "sigma_s");
  check_power(m.c.emission, what, "emission");
  if (m.field) check_field(*m.field, textures_.size(), what);
  if (added_media_ >= static_cast<size_t>(std::numeric_limits<int16_t>::max()))
    fail(what, "a scene takes at most 32767 media");
  m.bound_by_constants();
  m.uses.clear();
  media_.resize(added_media_);  // the copies go (build() makes them again)
  media_.push_back(std::move(m));
  added_media_ = media_.size();
  invalidate_lights();
  return static_cast<uint32_t>(added_media_ - 1);
}

void Scene::set_world_medium(int medium) {
  ensure_mutable();
  if (medium < -1 || medium >= static_cast<int>(added_media_))
    fail("world", "medium index " + std::to_string(medium) + " out of range (scene has " +
                      std::to_string(added_media_) + " media)");
  if (medium >= 0 && media_[static_cast<size_t>(medium)].field)
    fail("world", quoted("medium", media_[static_cast<size_t>(medium)].name) +
                      " varies in space: a world medium must be homogeneous");
  world_medium_ = medium;
  lights_built_ = false;  // the media's sums with the world's (combine_overlapping_media)
}

void Scene::set_material_medium(uint32_t material, int medium, bool surface) {
  ensure_mutable();
  check_material(material, "material " + std::to_string(material));
  const std::string what = quoted("material", materials_[material].name);
  if (medium < -1 || medium >= static_cast<int>(added_media_))
    fail(what, "medium index " + std::to_string(medium) + " out of range (scene has " +
                   std::to_string(added_media_) + " media)");
  if (!surface && materials_[material].emits())
    fail(what, "a boundary without a surface cannot emit (give the medium emission instead)");
  materials_[material].medium = medium;
  materials_[material].surface = surface;
  invalidate_lights();
}

bool Scene::has_mesh_media() const {
  for (const Material& m : materials_)
    if (m.medium >= 0) return true;
  return false;
}

bool Scene::has_media() const {
  if (world_medium_ >= 0) return true;
  for (const Material& m : materials_)
    if (m.medium >= 0 || !m.surface) return true;
  return false;
}

namespace {

// Directions of the rays media_at casts: oblique to the axes, so that a box's edges and faces are
// not met edge-on, and apart from each other.
const Vec3 kInsideDirections[3] = {glm::normalize(Vec3(0.5377, 0.3619, 0.7614)),
                                   glm::normalize(Vec3(-0.6823, 0.5934, -0.4271)),
                                   glm::normalize(Vec3(0.2147, -0.8612, 0.3338))};
constexpr int kInsideRays = 3;
constexpr int kMaxInsideHits = 4096;  // surfaces passed along one ray before it gives up

// Along one ray from a point: per medium the boundaries left minus those entered (positive: the
// point is inside), and the distance to the first one left (the innermost medium's is nearest).
struct MediaAlongRay {
  std::vector<int> net;
  std::vector<double> first_exit;
};

}  // namespace

MediumStack Scene::media_at(const Vec3& p, uint8_t ray_kind) const {
  MediumStack out;
  if (!has_mesh_media()) return out;
  MediaAlongRay along[kInsideRays];
  for (int k = 0; k < kInsideRays; ++k) {
    MediaAlongRay& a = along[k];
    a.net.assign(media_.size(), 0);
    a.first_exit.assign(media_.size(), kInf);
    Ray ray{p, kInsideDirections[k], ray_kind};
    double travelled = 0.0;
    Hit hit;
    for (int n = 0; n < kMaxInsideHits && intersect(ray, hit); ++n) {
      travelled += hit.t;
      const int id = medium_in(hit.material, hit.object);
      if (id >= 0) {
        const bool leaving = glm::dot(ray.direction, hit.geometric_normal) > 0.0;
        a.net[id] += leaving ? 1 : -1;
        if (leaving) a.first_exit[id] = std::min(a.first_exit[id], travelled);
      }
      ray.origin = offset_point(hit.position, hit.geometric_normal, ray.direction, offset_floor());
    }
  }
  // A medium holds the point if most rays leave it more often than they enter, as many times as the
  // fewest of those leave it more (two objects of one medium: twice, as `cross` counts); the
  // outermost (the farthest first exit) goes on the stack first.
  struct Inside {
    double exit;
    int id, times;
  };
  std::vector<Inside> inside;
  for (size_t id = 0; id < media_.size(); ++id) {
    int votes = 0, times = kMaxInsideHits;
    double exit = 0.0;
    for (const MediaAlongRay& a : along)
      if (a.net[id] > 0) ++votes, exit = std::max(exit, a.first_exit[id]), times = std::min(times, a.net[id]);
    if (2 * votes > kInsideRays) inside.push_back({exit, static_cast<int>(id), times});
  }
  std::sort(inside.begin(), inside.end(), [](const Inside& a, const Inside& b) { return a.exit > b.exit; });
  for (const Inside& in : inside)
    for (int k = 0; k < std::min(in.times, kMaxMediumStack); ++k) out.enter(in.id);
  return out;
}

namespace {

constexpr size_t kMaxCombinedMedia = 1024;
constexpr size_t kMaxTripleRegions = 64;  // objects with media beyond which only pairs are summed

// The sum of media `ids`: coefficients and emission added; the phase the scattering-weighted
// mixture where two single-lobe phases meet (exact), otherwise the strongest scatterer's.
Medium sum_of_media(const std::vector<Medium>& media, const int16_t* ids, int count) {
  Medium sum;
  sum.name = "sum";
  const Medium* strongest = &media[ids[0]];
  for (int k = 0; k < count; ++k) {
    const Medium& m = media[ids[k]];
    sum.name += " '" + m.name + "'";
    sum.c.sigma_a += m.c.sigma_a, sum.c.sigma_s += m.c.sigma_s, sum.c.emission += m.c.emission;
    sum.sigma_t_bound += m.sigma_t_bound, sum.sigma_s_bound += m.sigma_s_bound;
    sum.emission_bound += m.emission_bound;
    sum.uses.insert(sum.uses.end(), m.uses.begin(), m.uses.end());
    sum.majorant_grids.insert(sum.majorant_grids.end(), m.majorant_grids.begin(), m.majorant_grids.end());
    sum.majorant_rest += m.majorant_grids.empty() ? max_component(m.sigma_t_bound) : m.majorant_rest;
    sum.rest_emits = sum.rest_emits || (m.majorant_grids.empty() ? m.emits() : m.rest_emits);
    if (luminance(m.c.sigma_s) > luminance(strongest->c.sigma_s)) strongest = &m;
  }
  sum.c.phase = strongest->c.phase;
  const Medium &a = media[ids[0]], &b = media[ids[count - 1]];
  const double sa = luminance(a.c.sigma_s), sb = luminance(b.c.sigma_s);
  if (count == 2 && a.c.phase.second_weight == 0.0 && b.c.phase.second_weight == 0.0 && sa + sb > 0.0) {
    sum.c.phase.first = a.c.phase.first;
    sum.c.phase.second = b.c.phase.first;
    sum.c.phase.second_weight = sb / (sa + sb);
  }
  sum.sigma_t = sum.c.sigma_t();
  if (sum.majorant_grids.size() > kMaxSummedGrids) sum.majorant_grids.clear();  // one majorant, as without
  return sum;
}

// The distinct media of `stack`, and `world` if it is one (>= 0), ascending; returns how many
// (`ids` holds kMaxMediumStack + 1).
int distinct_media(const MediumStack& stack, int world, int16_t* ids) {
  int n = 0;
  for (int k = 0; k <= stack.count; ++k) {
    if (k == stack.count && world < 0) break;
    const int16_t id = k < stack.count ? stack.ids[k] : static_cast<int16_t>(world);
    int j = n;
    while (j > 0 && ids[j - 1] > id) --j;
    if (j > 0 && ids[j - 1] == id) continue;
    for (int i = n; i > j; --i) ids[i] = ids[i - 1];
    ids[j] = id, ++n;
  }
  return n;
}

}  // namespace

const Medium* Scene::combined_medium(const MediumStack& stack) const {
  int16_t ids[kMaxMediumStack + 1];
  const int n = distinct_media(stack, stack.count > 0 ? world_medium_ : -1, ids);
  if (n == 1) return &media_[static_cast<size_t>(ids[0])];
  for (const CombinedMedium& c : combined_media_)
    if (c.count == n && std::equal(ids, ids + n, c.ids)) return &c.medium;
  return &media_[stack.top(world_medium_)];  // overlapping media build() did not foresee
}

// Every pair, and triple, of media whose objects' boxes overlap gets its sum, so that a path in
// both finds it (combined_medium); with a world medium, every mesh medium and every such sum gets
// one with the world's too (Cycles' volume stack starts with the world's volume, and a mesh's adds
// to it); up to kMaxCombinedMedia.
void Scene::combine_overlapping_media() {
  combined_media_.clear();
  std::vector<std::pair<int16_t, Aabb>> regions;  // a medium and the box of one object's primitives of it
  for (const auto& [key, box] : media_boxes_) {
    if (regions.size() >= kMaxCombinedMedia) break;
    regions.push_back({static_cast<int16_t>(key.second), box});
  }
  auto overlap = [](const Aabb& a, const Aabb& b) {
    return glm::all(glm::lessThan(glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)));
  };
  auto add = [&](std::vector<int16_t> ids) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    if (ids.size() < 2 || combined_media_.size() >= kMaxCombinedMedia) return;
    for (const CombinedMedium& c : combined_media_)
      if (c.count == ids.size() && std::equal(ids.begin(), ids.end(), c.ids)) return;
    CombinedMedium c;
    c.count = static_cast<uint8_t>(ids.size());
    std::copy(ids.begin(), ids.end(), c.ids);
    c.medium = sum_of_media(media_, c.ids, c.count);
    combined_media_.push_back(std::move(c));
  };
  for (size_t i = 0; i < regions.size(); ++i)
    for (size_t j = i + 1; j < regions.size(); ++j) {
      if (!overlap(regions[i].second, regions[j].second)) continue;
      add({regions[i].first, regions[j].first});
      for (size_t k = j + 1; k < regions.size() && regions.size() <= kMaxTripleRegions; ++k)
        if (overlap(regions[i].second, regions[k].second) && overlap(regions[j].second, regions[k].second))
          add({regions[i].first, regions[j].first, regions[k].first});
    }
  if (world_medium_ < 0) return;
  const size_t sums = combined_media_.size();
  const int16_t world = static_cast<int16_t>(world_medium_);
  for (const auto& region : regions) add({region.first, world});
  for (size_t k = 0; k < sums; ++k) {
    std::vector<int16_t> ids(combined_media_[k].ids, combined_media_[k].ids + combined_media_[k].count);
    ids.push_back(world);
    add(ids);
  }
}

// The camera's media (media_at its position), and whether any ray can start where the media
// differ: the box of the rays' origins (the near plane's corners, or the orthographic window's,
// widened by the aperture) meets the box of an object with a medium.
void Scene::place_camera_in_media() {
  camera_media_ = media_at(camera_.position(), kCameraRay);
  rays_start_near_media_ = false;
  if (!has_mesh_media()) return;
  Aabb origins;
  origins.grow(camera_.position());
  for (const double px : {0.0, double(camera_.width)})
    for (const double py : {0.0, double(camera_.height)}) origins.grow(camera_.generate_ray(px, py).origin);
  const Vec3 widen(camera_.aperture_radius + ray_offset(camera_.position(), offset_floor()));
  origins.lo -= widen, origins.hi += widen;
  for (const auto& [key, box] : media_boxes_)
    if (origins.touches(box)) rays_start_near_media_ = true;
}

MediumStack Scene::media_along(MediumStack stack, const Vec3& from, const Vec3& to, uint8_t ray_kind) const {
  const Vec3 d = to - from;
  double distance = glm::length(d);
  if (!(distance > 0.0)) return stack;
  Ray ray{from, d / distance, ray_kind};
  Hit hit;
  for (int crossing = 0; crossing < kMaxMediumCrossings && intersect(ray, hit, distance); ++crossing) {
    cross(hit, ray.direction, stack);
    distance -= hit.t;
    ray.origin = offset_point(hit.position, hit.geometric_normal, ray.direction, offset_floor());
  }
  return stack;
}

std::map<std::pair<uint32_t, int>, Aabb> Scene::medium_boxes(bool copies) const {
  std::map<std::pair<uint32_t, int>, Aabb> boxes;
  auto grow = [&](uint32_t material, uint32_t object, const Aabb& box) {
    const int id = copies ? medium_in(material, object) : materials_[material].medium;
    if (id >= 0) boxes[{object, id}].grow(box);
  };
  geometry_.for_each_primitive_box(grow);
  return boxes;
}

namespace {
// The box of the points a light's photons leave from.
Aabb light_extent(const Light& l) {
  Aabb box;
  if (l.kind == LightKind::Rectangle || l.kind == LightKind::Disk) {
    for (const double u : {-1.0, 1.0})
      for (const double v : {-1.0, 1.0}) box.grow(l.position + u * l.axis_u + v * l.axis_v);
  } else {
    box.grow(l.position - Vec3(l.radius));
    box.grow(l.position + Vec3(l.radius));
  }
  return box;
}
}  // namespace

// Whether `box` reaches into the box of a mesh medium without lying inside it (conservative: the
// media's boxes, not their meshes).
bool Scene::crosses_medium_boundary(const Aabb& box) const {
  for (const auto& [key, medium_box] : media_boxes_) {
    const bool inside = glm::all(glm::greaterThan(box.lo, medium_box.lo)) && glm::all(glm::lessThan(box.hi, medium_box.hi));
    if (box.touches(medium_box) && !inside) return true;
  }
  return false;
}

void Scene::place_lights_in_media() {
  if (!has_mesh_media()) return;
  std::map<uint32_t, MediumStack> object_media;  // emitting meshes: one point of each object's first light decides
  for (Light& l : lights_) {
    switch (l.kind) {
      case LightKind::Point: case LightKind::Sphere: case LightKind::Spot: case LightKind::Rectangle:
      case LightKind::Disk:
        l.media = media_at(l.position, kShadowRay);  // a photon leaves its light as a shadow ray
        l.straddles_media = crosses_medium_boundary(light_extent(l));
        break;
      case LightKind::Triangle: {
        const uint32_t object = geometry_.triangle_object(l.primitive);
        auto found = object_media.find(object);
        if (found == object_media.end()) {
          const TrianglePrim& t = l.triangle;
          const Vec3 centre = t.v0 + (t.e1 + t.e2) / 3.0, normal = glm::normalize(glm::cross(t.e1, t.e2));
          const Vec3 off = centre + 4.0 * ray_offset(centre, offset_floor()) * normal;
          found = object_media.emplace(object, media_at(off, kShadowRay)).first;
        }
        l.media = found->second;
        break;
      }
      case LightKind::Medium: {  // an emitting region: the media at a point inside it, its own on top
        const int own = medium_regions_[l.region].medium;
        Rng rng(0, l.region, 0);
        Vec3 inside;
        if (sample_medium_region(l.region, rng, inside)) l.media = media_at(inside, kShadowRay);
        if (l.media.top(-1) != own) l.media.enter(own);
        break;
      }
      default:
        break;
    }
  }
}

Color Scene::shadow_transmittance(const Ray& shadow, double distance, MediumStack stack, Rng& rng) const {
  Color tr(1.0);
  Ray ray = shadow;
  for (int crossing = 0; crossing <= kMaxMediumCrossings; ++crossing) {
    Hit hit;
    const bool found = intersect(ray, hit, distance);
    if (const Medium* m = medium_of(stack)) {
      const double segment = found ? hit.t : distance;
      tr *= m->extinction_varies() ? track(*m, ray, segment, tr, false, false, rng).weight
                                  : transmittance(m->sigma_t, segment);
    }
    if (!found) return tr;
    if (materials_[hit.material].surface) return Color(0.0);
    if (!(max_component(tr) > 0.0)) return Color(0.0);
    cross(hit, ray.direction, stack);
    distance -= hit.t;
    ray.origin = offset_point(hit.position, hit.geometric_normal, ray.direction, offset_floor());
    if (!(distance > 0.0)) return tr;
  }
  return Color(0.0);
}

void Scene::set_majorant_grids(bool on) {
  ensure_mutable();
  if (on == majorant_grids_) return;
  majorant_grids_ = on;
  invalidate_lights();  // build() prepares the media again
}

}  // namespace ppm
