// Many rays cast at once (Scene.intersect from Python: the data passes, tests, tools). Chunks of rays
// are handed out from a shared counter, so a thread slowed by other load on the machine does not hold
// the batch up, and each chunk is cast in groups, so the scene can interleave their traversals.
#pragma once

#include "base/parallel.h"
#include "scene/scene.h"

#include <algorithm>
#include <atomic>
#include <vector>

namespace ppm {

// Casts rays i in [0, n), each made by ray_at(i), on `threads` threads (0: all), and hands every
// ray's hit to hit_at(i, hit). The scene must be built.
template <class RayAt, class HitAt>
void intersect_batch(const Scene& scene, size_t n, int threads, const RayAt& ray_at, const HitAt& hit_at) {
  constexpr size_t kChunk = 4096, kGroup = 256;
  std::atomic<bool> never{false};
  const auto cast_chunk = [&](int, size_t chunk) {
    std::vector<Ray> rays(kGroup);  // on the heap: 40 KB would crowd a small thread stack
    std::vector<Hit> hits(kGroup);
    const size_t end = std::min(n, (chunk + 1) * kChunk);
    for (size_t first = chunk * kChunk; first < end; first += kGroup) {
      const size_t count = std::min(kGroup, end - first);
      for (size_t b = 0; b < count; ++b) rays[b] = ray_at(first + b);
      scene.intersect_many(rays.data(), count, hits.data());
      for (size_t b = 0; b < count; ++b) hit_at(first + b, hits[b]);
    }
  };
  parallel_chunks(threads > 0 ? threads : hardware_threads(), (n + kChunk - 1) / kChunk, cast_chunk, never, nullptr,
                  0.0);
}

// Rays given as arrays of 3 doubles each (Scene.intersect): an origin and a direction of any length.
// Throws std::invalid_argument naming the first origin that is not finite or direction that is zero
// or not finite ("intersect: origin 3 is not finite").
void check_ray_arrays(const double* origins, const double* directions, size_t n);

// Where each ray's hit goes: t (inf on a miss), the geometric normal (3 doubles, 0 on a miss), the
// primitive, object and material (-1 on a miss).
struct HitArrays {
  double* t;
  double* normal;
  int64_t* primitive;
  int64_t* object;
  int64_t* material;
};

// Casts the rays check_ray_arrays accepted, of kind `kind` (kAllRayKinds: everything visible), on
// `threads` threads (0: all), into `out`. The scene must be built.
void intersect_arrays(const Scene& scene, const double* origins, const double* directions, size_t n, uint8_t kind,
                      int threads, const HitArrays& out);

}  // namespace ppm
