// Rays cast from arrays of numbers (Scene.intersect): their checks, and their hits into arrays.
#include "scene/ray_batch.h"

#include <stdexcept>
#include <string>

namespace ppm {

void check_ray_arrays(const double* origins, const double* directions, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    const Vec3 org(origins[3 * i], origins[3 * i + 1], origins[3 * i + 2]);
    const Vec3 dir(directions[3 * i], directions[3 * i + 1], directions[3 * i + 2]);
    if (!is_finite(org)) throw std::invalid_argument("intersect: origin " + std::to_string(i) + " is not finite");
    Vec3 unit_dir;
    if (!unit_direction(dir, unit_dir))
      throw std::invalid_argument("intersect: direction " + std::to_string(i) + " is zero or not finite");
  }
}

void intersect_arrays(const Scene& scene, const double* origins, const double* directions, size_t n, uint8_t kind,
                      int threads, const HitArrays& out) {
  intersect_batch(
      scene, n, threads,
      [&](size_t i) {
        Ray ray;
        unit_direction(Vec3(directions[3 * i], directions[3 * i + 1], directions[3 * i + 2]), ray.direction);
        ray.origin = Vec3(origins[3 * i], origins[3 * i + 1], origins[3 * i + 2]);
        ray.kind = kind;
        return ray;
      },
      [&](size_t i, const Hit& h) {
        const bool found = h.found();
        out.t[i] = found ? h.t : kInf;
        out.normal[3 * i] = found ? h.geometric_normal.x : 0.0;
        out.normal[3 * i + 1] = found ? h.geometric_normal.y : 0.0;
        out.normal[3 * i + 2] = found ? h.geometric_normal.z : 0.0;
        out.primitive[i] = found ? int64_t(h.primitive) : -1;  // (uint32_t : int would make -1 unsigned)
        out.object[i] = found ? int64_t(h.object) : -1;
        out.material[i] = found ? int64_t(h.material) : -1;
      });
}

}  // namespace ppm
