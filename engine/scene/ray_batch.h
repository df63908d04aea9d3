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

}  // namespace ppm
