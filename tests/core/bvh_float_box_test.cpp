// The BVH stores its boxes in float rounded outward and tests them in double.
// These cases check that no hit is lost where float rounding bites: geometry
// far from the origin, tiny and huge scales (down to float denormals and past
// float's range), axis-parallel rays, rays starting inside the boxes, and
// rays through shared edges and vertices. Each compares against brute force
// over the same double-precision triangle test, which must agree exactly.
#include "geometry/bvh.h"
#include "geometry/triangle.h"
#include "math/float_bounds.h"
#include "math/rng.h"
#include "bvh_test_helpers.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

#include <vector>

namespace ppm {
namespace {

// Random small triangles in a cube of side `scale` centred at `centre`.
TriangleSoup random_soup(Rng& rng, const Vec3& centre, double scale, int count) {
  TriangleSoup s;
  for (int i = 0; i < count; ++i)
    s.tris.push_back({centre + scale * unit_cube(rng), 0.05 * scale * unit_cube(rng), 0.05 * scale * unit_cube(rng)});
  s.build();
  return s;
}

// Rays from outside the cube (and from inside it, one in four) at points inside it.
void expect_matches_brute_force(const TriangleSoup& s, Rng& rng, const Vec3& centre, double scale, int rays) {
  int hits = 0;
  for (int i = 0; i < rays; ++i) {
    const Vec3 o = centre + scale * (i % 4 == 0 ? unit_cube(rng) : 3.0 * unit_cube(rng));
    const Vec3 target = centre + scale * unit_cube(rng);
    const Vec3 d = glm::normalize(target - o);
    if (!is_finite(d)) continue;
    const Ray r{o, d};
    const double expect = s.brute_t(r);
    ASSERT_EQ(s.bvh_t(r), expect) << "ray " << i << " scale " << scale;
    hits += expect < kInf;
  }
  EXPECT_GT(hits, rays / 20);
}

TEST(BvhFloatBox, RoundingIsOutward) {
  Rng rng(11, 12, 13);
  for (int i = 0; i < 100000; ++i) {
    const double x = (rng.uniform() - 0.5) * std::pow(10.0, rng.uniform() * 80.0 - 40.0);
    const float lo = float_down(x), hi = float_up(x);
    ASSERT_LE(double(lo), x);
    ASSERT_GE(double(hi), x);
    ASSERT_LE(std::nextafter(lo, kInf), hi) << "not the nearest floats around " << x;
  }
  EXPECT_EQ(float_up(1e300), std::numeric_limits<float>::infinity());
  EXPECT_EQ(float_down(1e300), std::numeric_limits<float>::max());
  EXPECT_EQ(float_down(-1e300), -std::numeric_limits<float>::infinity());
  EXPECT_GT(float_up(1e-300), 0.0f);  // the smallest denormal, not zero
  EXPECT_EQ(float_down(1e-300), 0.0f);
  EXPECT_EQ(float_up(0.5), 0.5f);  // exact values stay put
}

// The per-ray roundings of the origin: on the right side, and within two
// ulps of the exact ones, across scales, signs, zeros and the float range.
TEST(BvhFloatBox, LooseRoundingIsOutwardAndTight) {
  Rng rng(14, 15, 16);
  std::vector<double> xs = {0.0, -0.0, 1e-300, -1e-300, 0.5, -0.5, 3.4028234663852886e38, -3.4028234663852886e38,
                            1e300, -1e300, 1e-45, -1e-45, 1.0e-38, -1.0e-38};
  for (int i = 0; i < 100000; ++i)
    xs.push_back((rng.uniform() - 0.5) * std::pow(10.0, rng.uniform() * 90.0 - 45.0));
  for (const double x : xs) {
    const float above = float_above(x), below = float_below(x);
    ASSERT_FALSE(std::isnan(above) || std::isnan(below)) << x;
    ASSERT_GE(double(above), x);
    ASSERT_LE(double(below), x);
    constexpr float kFloatInfinity = std::numeric_limits<float>::infinity();
    ASSERT_LE(above, std::nextafter(float_up(x), kFloatInfinity)) << "more than two ulps above " << x;
    ASSERT_GE(below, std::nextafter(float_down(x), -kFloatInfinity)) << "more than two ulps below " << x;
  }
}

TEST(BvhFloatBox, FarFromOriginAndAcrossScales) {
  // Millimetre triangles 1000 km away: float spacing there (6 cm) is far
  // larger than the triangles, so every box is padded; nothing may be lost.
  // Then tiny (denormal-float) and huge (past float range) scenes.
  // (Scales stop where the double triangle test itself under- or overflows.)
  const struct {
    Vec3 centre;
    double scale;
  } cases[] = {{Vec3(1e6, -2e6, 3e5), 1e-3}, {Vec3(0.1, 0.2, 0.3), 1e-3}, {Vec3(0.0), 1e-40},
               {Vec3(0.0), 1e-100},         {Vec3(0.0), 1e38},             {Vec3(3e60, 0.0, -1e60), 1e50}};
  uint64_t seed = 1;
  for (const auto& c : cases) {
    Rng rng(21, 22, seed++);
    const TriangleSoup s = random_soup(rng, c.centre, c.scale, 1500);
    expect_matches_brute_force(s, rng, c.centre, c.scale, 2000);
  }
}

TEST(BvhFloatBox, AxisParallelRaysOnAGrid) {
  // A height field of triangles at coordinates float cannot represent (0.1
  // steps offset by 1/3), cast at with axis-parallel rays, including ones
  // that run exactly along grid lines, shared edges and vertices.
  TriangleSoup s;
  const int n = 24;
  const double h = 0.1, off = 1.0 / 3.0;
  auto z = [](int i, int j) { return 0.01 * ((i * 7 + j * 13) % 5); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Vec3 p00(off + i * h, off + j * h, z(i, j)), p10(off + (i + 1) * h, off + j * h, z(i + 1, j));
      const Vec3 p01(off + i * h, off + (j + 1) * h, z(i, j + 1));
      const Vec3 p11(off + (i + 1) * h, off + (j + 1) * h, z(i + 1, j + 1));
      s.tris.push_back({p00, p10 - p00, p11 - p00});
      s.tris.push_back({p00, p11 - p00, p01 - p00});
    }
  s.build();
  int hits = 0;
  for (int i = 0; i <= 4 * n; ++i)
    for (int j = 0; j <= 4 * n; ++j) {
      const double x = off + i * h / 4, y = off + j * h / 4;  // on edges and vertices every 4th step
      for (const Vec3& d : {Vec3(0, 0, -1), Vec3(-0.0, 0.0, 1.0)}) {
        const Ray r{Vec3(x, y, d.z < 0 ? 1.0 : -1.0), d};
        const double expect = s.brute_t(r);
        ASSERT_EQ(s.bvh_t(r), expect) << i << " " << j;
        hits += expect < kInf;
      }
      // Horizontal rays through the sheet's layers, along x and along y.
      for (const Ray& r : {Ray{Vec3(-1.0, y, 0.02), Vec3(1, 0, 0)}, Ray{Vec3(x, 5.0, 0.015), Vec3(0, -1, 0)}})
        ASSERT_EQ(s.bvh_t(r), s.brute_t(r)) << i << " " << j;
    }
  EXPECT_GT(hits, 4 * n * n);
}

TEST(BvhFloatBox, MixedSizesAndDegenerateTriangles) {
  // One huge triangle over many small ones, slivers, zero-area triangles,
  // and many triangles sharing one centroid: boxes overlap heavily.
  Rng rng(31, 32, 33);
  TriangleSoup s;
  s.tris.push_back({Vec3(-1e4, -1e4, 0.0), Vec3(3e4, 0.0, 0.0), Vec3(0.0, 3e4, 1e-3)});
  for (int i = 0; i < 1000; ++i) s.tris.push_back({unit_cube(rng), 0.01 * unit_cube(rng), 0.01 * unit_cube(rng)});
  for (int i = 0; i < 300; ++i) {  // slivers: one edge a million times the other
    const Vec3 p = unit_cube(rng);
    s.tris.push_back({p, Vec3(0.5, 0.0, 0.0), Vec3(0.5, 1e-7, 1e-7)});
  }
  for (int i = 0; i < 200; ++i) s.tris.push_back({unit_cube(rng), Vec3(0.0), Vec3(0.0)});  // points
  for (int i = 0; i < 500; ++i) {  // shared centroid at the origin
    const double r = 0.01 + rng.uniform();
    s.tris.push_back({Vec3(-r, -r, -0.5 * r), Vec3(2 * r, 0.0, r), Vec3(0.0, 2 * r, 0.5 * r)});
  }
  s.build();
  expect_matches_brute_force(s, rng, Vec3(0.0), 1.0, 3000);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 o = 3.0 * unit_cube(rng);
    const Ray r{o, glm::normalize(unit_cube(rng) - o)};
    const double t = s.brute_t(r), limit = 0.5 + 4.0 * rng.uniform();
    ASSERT_EQ(s.bvh_any(r, limit), t < limit) << "ray " << i;
  }
}

TEST(BvhFloatBox, OriginsBeyondFloatRange) {
  // Rays from 1e38 away, past what the float slab test covers: the BVH
  // falls back to testing every primitive and must still agree.
  Rng rng(51, 52, 53);
  const TriangleSoup s = random_soup(rng, Vec3(0.0), 1.0, 300);
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 o = Vec3(1e38, -2e38, 0.5e38) * (1.0 + rng.uniform());
    const Ray r{o, glm::normalize(s.tris[i].v0 + 0.2 * s.tris[i].e1 + 0.2 * s.tris[i].e2 - o)};
    const double expect = s.brute_t(r);
    ASSERT_EQ(s.bvh_t(r), expect) << "ray " << i;
    ASSERT_EQ(s.bvh_any(r, kInf), expect < kInf) << "ray " << i;
    hits += expect < kInf;
  }
  EXPECT_GT(hits, 0);
}

TEST(BvhFloatBox, SmallTreesAndEmptyLanes) {
  // 1 to 9 triangles: a root that is a single leaf, and nodes with unused
  // children, which every ray must miss.
  Rng rng(41, 42, 43);
  for (int count = 1; count <= 9; ++count) {
    const TriangleSoup s = random_soup(rng, Vec3(0.0), 1.0, count);
    for (int i = 0; i < 500; ++i) {
      const Vec3 o = 3.0 * unit_cube(rng);
      const Ray r{o, glm::normalize(s.tris[i % count].v0 + 0.3 * s.tris[i % count].e1 + 0.3 * s.tris[i % count].e2 - o)};
      ASSERT_EQ(s.bvh_t(r), s.brute_t(r)) << count << " triangles, ray " << i;
    }
  }
  Bvh empty;
  empty.build({});
  double tmax = kInf;
  empty.closest(Vec3(0.0), Vec3(0, 0, 1), tmax, [](uint32_t, double&) { return true; });
  EXPECT_EQ(tmax, kInf);
}

}  // namespace
}  // namespace ppm
