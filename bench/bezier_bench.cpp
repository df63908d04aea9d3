// Benchmark of BezierRevolve ray intersection: nanoseconds per ray for hits
// and misses, per ray as the BVH would pay it (slab test of every segment's
// box, exact test of the segments whose box is hit). Profiles: single cubic,
// single degree 6, 8-segment cubic chain, under a rotated, scaled, translated
// transform. The old report's method (tests/core/bezier_foil.h) is timed on
// the same rays for comparison.
//
// Build and run (from the repository root):
//   g++ -std=c++17 -O3 -DNDEBUG -Iengine -Itests/core bench/bezier_bench.cpp engine/math/bernstein.cpp engine/geometry/bezier_revolve.cpp -o /tmp/bezier_bench && /tmp/bezier_bench
#include "geometry/bezier_revolve.h"
#include "math/aabb.h"
#include "math/rng.h"

#include "bezier_foil.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

namespace {

using namespace ppm;

struct Profile {
  std::string name;
  std::vector<Vec2> pts;
  BezierProfileKind kind;
};

std::vector<Vec2> chain8() {
  std::vector<Vec2> pts;
  const double r[9] = {0.0, 0.9, 1.1, 0.7, 0.5, 0.8, 0.4, 0.35, 0.6};
  const double z[9] = {0.0, 0.05, 0.6, 1.1, 1.4, 1.9, 2.3, 2.7, 3.0};
  for (int k = 0; k <= 8; ++k) {
    const int a = k == 0 ? 0 : k - 1, b = k == 8 ? 8 : k + 1;
    const Vec2 tan = (k == 0 ? Vec2(0.9, 0.0) : Vec2(r[b] - r[a], z[b] - z[a]) / double(b - a));
    const Vec2 p(r[k], z[k]);
    if (k > 0) pts.push_back(p - tan / 3.0);
    pts.push_back(p);
    if (k < 8) pts.push_back(p + tan / 3.0);
  }
  return pts;
}

struct Sample {
  std::vector<Ray> hits, misses, box_misses;  // box_misses: hit some segment box, miss the surface
};

double trace(const BezierRevolve& s, const Ray& ray, const Vec3& inv) {
  double tmax = kInf;
  Hit h;
  for (size_t i = 0; i < s.segment_count(); ++i)
    if (slab_entry(s.segment_bounds(i), ray.origin, inv, tmax) < kInf && s.intersect_segment(i, ray, 0.0, tmax, h))
      tmax = h.t;
  return tmax;
}

Vec3 inverse_dir(const Vec3& d) { return Vec3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z); }

// Rays from a sphere of radius 2.5 R towards a random point of the bounding
// ball of radius R, split by outcome.
Sample make_rays(const BezierRevolve& s, const Vec3& center, double R, int count) {
  Sample out;
  Rng rng(1, 2, 3);
  auto sphere = [&]() {
    const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform(), q = std::sqrt(1 - z * z);
    return Vec3(q * std::cos(phi), q * std::sin(phi), z);
  };
  for (int i = 0; i < count; ++i) {
    const Vec3 o = center + 2.5 * R * sphere();
    const Vec3 target = center + R * std::cbrt(rng.uniform()) * sphere();
    const Ray ray{o, glm::normalize(target - o)};
    const Vec3 inv = inverse_dir(ray.direction);
    if (trace(s, ray, inv) < kInf) {
      out.hits.push_back(ray);
      continue;
    }
    out.misses.push_back(ray);
    for (size_t k = 0; k < s.segment_count(); ++k)
      if (slab_entry(s.segment_bounds(k), ray.origin, inv, kInf) < kInf) {
        out.box_misses.push_back(ray);
        break;
      }
  }
  return out;
}

// CPU time of this process: the machine is shared, wall time would count
// other processes' slices.
double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

template <class F>
double ns_per_ray(const std::vector<Ray>& rays, F&& f) {
  if (rays.empty()) return 0.0;
  double best = 1e300, sink = 0.0;
  for (int rep = 0; rep < 3; ++rep) {
    long n = 0;
    const double t0 = cpu_seconds();
    double elapsed = 0.0;
    do {
      for (const Ray& r : rays) sink += f(r);
      n += long(rays.size());
      elapsed = cpu_seconds() - t0;
    } while (elapsed < 0.3);
    best = std::min(best, 1e9 * elapsed / double(n));
  }
  if (sink == 12345.678) std::printf(" ");  // keep the work observable
  return best;
}

}  // namespace

int main() {
  const Mat4 I(1.0);
  const Mat4 m = glm::translate(I, Vec3(3, -2, 5)) * glm::rotate(I, 0.7, glm::normalize(Vec3(1, 2, 3))) *
                 glm::scale(I, Vec3(2.0));
  const std::vector<Profile> profiles = {
      {"single cubic", {{0.6, 0.0}, {1.6, 0.6}, {0.1, 1.4}, {0.7, 2.0}}, BezierProfileKind::SingleCurve},
      {"single degree 6",
       {{0.5, 0.0}, {1.2, 0.3}, {0.4, 0.8}, {1.3, 1.2}, {0.2, 1.6}, {0.9, 2.1}, {0.6, 2.5}},
       BezierProfileKind::SingleCurve},
      {"8-segment cubic chain", chain8(), BezierProfileKind::CubicChain},
  };
  std::printf("%-24s %5s | %9s %9s %12s | %8s %8s | %s\n", "profile", "segs", "hit ns", "miss ns",
              "box-miss ns", "foil hit", "foil miss", "rays hit/miss/box-miss");
  for (const Profile& p : profiles) {
    const BezierRevolve s(p.pts, p.kind, m);
    const bezfoil::Foil foil = bezfoil::make(p.pts, p.kind == BezierProfileKind::CubicChain, m);
    double zlo = 1e300, zhi = -1e300, rmax = 0;
    for (const Vec2& q : p.pts) zlo = std::min(zlo, q.y), zhi = std::max(zhi, q.y), rmax = std::max(rmax, q.x);
    const Vec3 center = Vec3(m * glm::dvec4(0, 0, 0.5 * (zlo + zhi), 1));
    const double R = 2.0 * std::sqrt(rmax * rmax + 0.25 * (zhi - zlo) * (zhi - zlo));
    const Sample rays = make_rays(s, center, R, 20000);
    auto ours = [&](const Ray& r) { return trace(s, r, inverse_dir(r.direction)); };
    auto old = [&](const Ray& r) {
      double t;
      return bezfoil::intersect(foil, r.origin, r.direction, 0.0, kInf, t) ? t : 0.0;
    };
    std::printf("%-24s %5zu | %9.1f %9.1f %12.1f | %8.1f %8.1f | %zu/%zu/%zu\n", p.name.c_str(), s.segment_count(),
                ns_per_ray(rays.hits, ours), ns_per_ray(rays.misses, ours), ns_per_ray(rays.box_misses, ours),
                ns_per_ray(rays.hits, old), ns_per_ray(rays.misses, old), rays.hits.size(), rays.misses.size(),
                rays.box_misses.size());
  }
  return 0;
}
