// Emitting media as lights (see Scene's "Emitting media as lights"): each object whose material
// carries an emitting medium encloses a region of it, a light of kind Medium whose power is
// 4 pi L_e V. Its photons start at uniform points inside (rejection in the region's box, inside by
// ray parity against the region's own triangles) in uniform directions (photon_tracer_media.h).
//
// The world's medium fills infinite space: its emission's power is unbounded, so it emits no
// photons (its light reaches the eye along eye rays only), and prepare_medium_lights says so.
#include "geometry/mesh_volume.h"
#include "math/sampling.h"
#include "scene/input_checks.h"
#include "scene/scene.h"

#include <map>
#include <utility>

namespace ppm {
using namespace scene_input;

void Scene::prepare_medium_lights(const Aabb& light_bounds) {
  medium_regions_.clear();
  light_notes_.clear();
  bool any = false;
  for (const Medium& m : media_) any = any || m.emits();
  if (!any) return;  // the common case: no triangle is looked at
  if (world_medium_ >= 0 && media_[world_medium_].emits())
    light_notes_.push_back("photons from the world medium's emission: unbounded power (seen along eye rays only)");
  // The triangles of each (object, emitting medium), as the mesh stores their corners.
  std::map<std::pair<uint32_t, int>, std::vector<TriangleCorners>> regions;
  for (uint32_t i = 0; i < geometry_.triangle_count(); ++i) {
    const uint32_t object = geometry_.triangle_object(i);
    const int medium = medium_in(geometry_.triangle_material(i), object);
    if (medium < 0 || !media_[medium].emits()) continue;
    regions[{object, medium}].push_back(geometry_.triangle_corners(i));
  }
  for (const auto& [key, triangles] : regions) {
    const Medium& m = media_[key.second];
    const std::string what = quoted("medium", m.name) + " in object " + std::to_string(key.first);
    const size_t open = open_edges(triangles);
    const double volume = std::fabs(signed_volume(triangles));
    // Open, its volume is not defined (nor is inside); enclosing nothing, it has no power.
    if (open > 0 || !(volume > 0.0) || !std::isfinite(volume)) {
      light_notes_.push_back("photons from " + what + ": " +
                             (open > 0 ? std::to_string(open) + " open edges (not a closed mesh)" : "no volume"));
      continue;
    }
    MediumRegion r{key.first, key.second, Aabb{}, volume};
    for (const TriangleCorners& t : triangles)
      for (const Vec3& c : t) r.box.grow(c);
    Light l;
    l.kind = LightKind::Medium;
    l.name = what;
    l.power = m.emission_bound;  // where it varies, each photon carries its point's share (emit_media_photon)
    l.position = r.box.center();
    l.region = static_cast<uint32_t>(medium_regions_.size());
    l.volume = volume;
    prepare_light(l, light_bounds);
    medium_regions_.push_back(r);
    lights_.push_back(l);
  }
}

bool Scene::inside_medium_region(uint32_t region, const Vec3& p, const Vec3& direction) const {
  const MediumRegion& r = medium_regions_[region];
  Ray ray{p, direction, kAllRayKinds};
  bool inside = false;
  // Each step passes one surface; a ray through more than this many is taken as outside.
  for (int crossing = 0; crossing < 4 * kMaxMediumCrossings; ++crossing) {
    Hit hit;
    if (!intersect(ray, hit)) return inside;
    if (hit.object == r.object && hit.primitive < geometry_.triangle_count() &&
        medium_in(hit.material, hit.object) == r.medium)
      inside = !inside;
    ray.origin = offset_point(hit.position, hit.geometric_normal, ray.direction, offset_floor());
  }
  return false;
}

bool Scene::sample_medium_region(uint32_t region, Rng& rng, Vec3& point) const {
  const MediumRegion& r = medium_regions_[region];
  const Vec3 extent = r.box.extent();
  for (int attempt = 0; attempt < kRegionTries; ++attempt) {
    const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    point = r.box.lo + Vec3(u1, u2, u3) * extent;
    // A direction of its own for each point: a ray along an edge of the mesh would count it twice.
    const double v1 = rng.uniform(), v2 = rng.uniform();
    if (inside_medium_region(region, point, sample_uniform_sphere(v1, v2))) return true;
  }
  return false;
}

}  // namespace ppm
