// Micro benchmark of the two PPM spatial indices on a unit Cornell box (five
// walls: x = 0, x = 1, y = 0, y = 1, z = 1). Mode A: 1.2M hit points as spheres
// (radius 0.002-0.01) queried by 1M photon positions. Mode B: 1M photon points
// queried by 300k hit-point boxes. Single-threaded; build and query times are
// the best of a few runs in thread CPU time, and every configuration must find
// the same total.
// "ns/q sort" repeats the queries with the items (hit points or photons) stored
// in Morton order, as a caller could keep them.
//
// Build and run (from /work/main; one line):
// g++ -std=c++17 -O3 -DNDEBUG -Wall -Wextra -I/work/main/engine bench/grid_bench.cpp engine/ppm/quantile_grid.cpp engine/ppm/hash_grid.cpp -o /tmp/grid_bench && /tmp/grid_bench
#include "math/rng.h"
#include "ppm/hash_grid.h"
#include "ppm/quantile_grid.h"

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

namespace {

using ppm::Vec3;

constexpr double kRadiusMin = 0.002, kRadiusMax = 0.01;

// CPU time of this thread: the machine is shared, and wall time mostly measured
// the neighbours' compile jobs.
double thread_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

Vec3 wall_point(ppm::Rng& rng) {
  const int wall = std::min(4, static_cast<int>(rng.uniform() * 5.0));
  const double u = rng.uniform(), v = rng.uniform();
  switch (wall) {
    case 0: return Vec3(0.0, u, v);
    case 1: return Vec3(1.0, u, v);
    case 2: return Vec3(u, 0.0, v);
    case 3: return Vec3(u, 1.0, v);
    default: return Vec3(u, v, 1.0);
  }
}

struct Spheres {
  std::vector<Vec3> centers;
  std::vector<double> radii;
  std::vector<double> r2;
};

Spheres wall_spheres(size_t n, uint64_t seed) {
  Spheres s;
  s.centers.resize(n);
  s.radii.resize(n);
  s.r2.resize(n);
  for (size_t i = 0; i < n; ++i) {
    ppm::Rng rng(seed, 0, i);
    s.centers[i] = wall_point(rng);
    s.radii[i] = kRadiusMin + (kRadiusMax - kRadiusMin) * rng.uniform();
    s.r2[i] = s.radii[i] * s.radii[i];
  }
  return s;
}

std::vector<Vec3> wall_points(size_t n, uint64_t seed) {
  std::vector<Vec3> points(n);
  for (size_t i = 0; i < n; ++i) {
    ppm::Rng rng(seed, 1, i);
    points[i] = wall_point(rng);
  }
  return points;
}

// Items sorted along a Morton curve: what a caller gains by storing hit points
// or photons in spatial order (the candidate loop reads their data).
std::vector<uint32_t> morton_order(const std::vector<Vec3>& points) {
  auto spread = [](uint64_t x) {  // 21 bits -> every third bit
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    return (x | x << 2) & 0x1249249249249249ull;
  };
  std::vector<uint64_t> code(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::u64vec3 q(glm::clamp(points[i], 0.0, 1.0) * 2097151.0);
    code[i] = spread(q.x) | spread(q.y) << 1 | spread(q.z) << 2;
  }
  std::vector<uint32_t> order(points.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return code[a] < code[b]; });
  return order;
}

Spheres permuted(const Spheres& s, const std::vector<uint32_t>& order) {
  Spheres out;
  for (uint32_t i : order) {
    out.centers.push_back(s.centers[i]);
    out.radii.push_back(s.radii[i]);
    out.r2.push_back(s.r2[i]);
  }
  return out;
}

struct Row {
  std::string name;
  double build_ms = 0.0, query_ms = 0.0, sorted_query_ms = 0.0;
  double candidates = 0.0, found = 0.0;  // per query
  size_t refs = 0, cells = 0, nonempty = 0, bytes = 0;
};

double best_time(int runs, const std::function<void()>& fn) {
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    const double t0 = thread_seconds();
    fn();
    best = std::min(best, thread_seconds() - t0);
  }
  return best;
}

// `param`: target items per cell (quantile grid) or cell size (hash grid).
void build_index(ppm::QuantileGrid& g, const std::vector<Vec3>& centers,
                 const std::vector<double>& radii, double param) {
  g = ppm::QuantileGrid(param);
  g.build(centers, radii);
}
void build_index(ppm::HashGrid& g, const std::vector<Vec3>& centers,
                 const std::vector<double>& radii, double param) {
  g.build(centers, radii, param);
}

// Mode A: photons look up the hit-point spheres containing them. Returns the
// query time; candidates and found are totals.
template <class Grid>
double time_point_queries(const Grid& grid, const Spheres& hits, const std::vector<Vec3>& photons,
                          uint64_t& candidates, uint64_t& found) {
  return 1e3 * best_time(2, [&] {
    candidates = found = 0;
    for (const Vec3& p : photons)
      grid.for_each_candidate_at(p, [&](uint32_t i) {
        ++candidates;
        const Vec3 d = p - hits.centers[i];
        found += glm::dot(d, d) <= hits.r2[i];
      });
  });
}

// Mode B: hit points gather the photons inside their boxes.
template <class Grid>
double time_box_queries(const Grid& grid, const std::vector<Vec3>& photons, const Spheres& hits,
                        uint64_t& candidates, uint64_t& found) {
  return 1e3 * best_time(2, [&] {
    candidates = found = 0;
    for (size_t h = 0; h < hits.centers.size(); ++h) {
      const Vec3& c = hits.centers[h];
      const double r = hits.radii[h], r2 = hits.r2[h];
      grid.for_each_candidate_in_box(c - r, c + r, [&](uint32_t i) {
        ++candidates;
        const Vec3 d = photons[i] - c;
        found += glm::dot(d, d) <= r2;
      });
    }
  });
}

template <class Grid>
Row run_mode_a(const std::string& name, double param, const Spheres& hits,
               const Spheres& sorted_hits, const std::vector<Vec3>& photons) {
  Row row;
  row.name = name;
  Grid grid;
  row.build_ms = 1e3 * best_time(3, [&] { build_index(grid, hits.centers, hits.radii, param); });
  uint64_t candidates = 0, found = 0, sorted_found = 0;
  row.query_ms = time_point_queries(grid, hits, photons, candidates, found);
  row.candidates = double(candidates) / photons.size();
  row.found = double(found) / photons.size();
  row.refs = grid.reference_count();
  row.cells = grid.cell_count();
  row.nonempty = grid.nonempty_cell_count();
  row.bytes = grid.memory_bytes();
  build_index(grid, sorted_hits.centers, sorted_hits.radii, param);
  row.sorted_query_ms = time_point_queries(grid, sorted_hits, photons, candidates, sorted_found);
  if (sorted_found != found) std::printf("MISMATCH %s\n", name.c_str());
  return row;
}

template <class Grid>
Row run_mode_b(const std::string& name, double param, const std::vector<Vec3>& photons,
               const std::vector<Vec3>& sorted_photons, const Spheres& hits) {
  Row row;
  row.name = name;
  Grid grid;
  row.build_ms = 1e3 * best_time(3, [&] { build_index(grid, photons, {}, param); });
  uint64_t candidates = 0, found = 0, sorted_found = 0;
  row.query_ms = time_box_queries(grid, photons, hits, candidates, found);
  row.candidates = double(candidates) / hits.centers.size();
  row.found = double(found) / hits.centers.size();
  row.refs = grid.reference_count();
  row.cells = grid.cell_count();
  row.nonempty = grid.nonempty_cell_count();
  row.bytes = grid.memory_bytes();
  build_index(grid, sorted_photons, {}, param);
  row.sorted_query_ms = time_box_queries(grid, sorted_photons, hits, candidates, sorted_found);
  if (sorted_found != found) std::printf("MISMATCH %s\n", name.c_str());
  return row;
}

void print_table(const char* title, size_t queries, const std::vector<Row>& rows) {
  std::printf("\n%s\n", title);
  std::printf("%-16s %8s %8s %9s %7s %7s %9s %8s %8s %7s\n", "index", "build ms", "ns/query",
              "ns/q sort", "cand/q", "found/q", "refs", "cells", "nonempty", "MB");
  for (const Row& r : rows)
    std::printf("%-16s %8.1f %8.1f %9.1f %7.1f %7.2f %9zu %8zu %8zu %7.1f\n", r.name.c_str(),
                r.build_ms, 1e6 * r.query_ms / queries, 1e6 * r.sorted_query_ms / queries,
                r.candidates, r.found, r.refs, r.cells, r.nonempty, r.bytes / 1048576.0);
}

std::string label(const char* kind, double param) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %g", kind, param);
  return buf;
}

void bench_mode_a() {
  const Spheres hits = wall_spheres(1200000, 1);
  const Spheres sorted_hits = permuted(hits, morton_order(hits.centers));
  const std::vector<Vec3> photons = wall_points(1000000, 2);
  std::vector<Row> rows;
  for (double t : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0})
    rows.push_back(run_mode_a<ppm::QuantileGrid>(label("quantile t", t), t, hits, sorted_hits, photons));
  for (double h : {0.006, 0.012, 0.02, 0.03})
    rows.push_back(run_mode_a<ppm::HashGrid>(label("hash h", h), h, hits, sorted_hits, photons));
  print_table("Mode A: 1.2M hit-point spheres (r 0.002-0.01), 1M photon point queries",
              photons.size(), rows);
}

void bench_mode_b() {
  const std::vector<Vec3> photons = wall_points(1000000, 3);
  std::vector<Vec3> sorted_photons;
  for (uint32_t i : morton_order(photons)) sorted_photons.push_back(photons[i]);
  const Spheres hits = wall_spheres(300000, 4);
  std::vector<Row> rows;
  for (double t : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0})
    rows.push_back(run_mode_b<ppm::QuantileGrid>(label("quantile t", t), t, photons, sorted_photons, hits));
  for (double h : {0.006, 0.012, 0.02, 0.03})
    rows.push_back(run_mode_b<ppm::HashGrid>(label("hash h", h), h, photons, sorted_photons, hits));
  print_table("Mode B: 1M photon points, 300k hit-point box queries (r 0.002-0.01)",
              hits.centers.size(), rows);
  // Reference for the split selection: a full sort of the three coordinate arrays.
  std::vector<double> coords(photons.size());
  const double sort_s = best_time(3, [&] {
    for (int a = 0; a < 3; ++a) {
      for (size_t i = 0; i < photons.size(); ++i) coords[i] = photons[i][a];
      std::sort(coords.begin(), coords.end());
    }
  });
  std::printf("std::sort of the 3 coordinate arrays of 1M photons: %.1f ms\n", 1e3 * sort_s);
}

}  // namespace

int main() {
  bench_mode_a();
  bench_mode_b();
  return 0;
}
