// Tests for BezierRevolve: analytic cases, constructor errors, and families of
// profiles x transforms x ray kinds compared with the independent long-double
// reference of bezier_reference.h (a scan along the ray, not a polynomial in
// the profile parameter). The old report's method (bezier_foil.h) runs on the
// same rays and its wrong-hit rate is printed next to ours.
//
// Tangency tolerance. A ray is excluded from the hit/miss and distance
// comparison only if the reference finds, before its nearest hit, a touch
// event with |g| < 1e-10 scale^2 (g = squared distance of the ray point from
// the axis minus r^2 at the same height: a meridian gap below ~5e-11 scale,
// or a ray crossing a profile end or turning circle that closely), or if its
// nearest hit meets the surface with |cos| < 1e-6. The implementation decides
// hit or miss at the noise floor of its polynomial (~1e-14 scale^2) and
// accepts a polished hit only below a 1e-11 residual, so outside this band
// both answers are determined; inside it, either answer is correct to the
// precision of the input. Excluded rays are still checked for NaN/Inf.
#include "geometry/bezier_revolve.h"

#include "bezier_foil.h"
#include "bezier_reference.h"
#include "math/rng.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace {

using namespace ppm;
using bezref::LD;

constexpr double kTouch = 1e-10;   // tangency band on |g| / scale^2
constexpr double kCos = 1e-6;      // tangency band on |cos(ray, normal)|
constexpr double kTolT = 1e-9;     // distance tolerance relative to the world scale

struct Family {
  std::string name;
  std::vector<Vec2> pts;
  BezierProfileKind kind;
};

// Eight-segment C1 chain (a bottle) from anchors with Catmull-Rom handles; it
// starts on the axis with a horizontal tangent (smooth pole) and has
// zero-length handles at anchor 4 (a cusp where the derivative vanishes).
std::vector<Vec2> bottle_chain() {
  const double r[9] = {0.0, 0.9, 1.1, 0.7, 0.5, 0.8, 0.4, 0.35, 0.6};
  const double z[9] = {0.0, 0.05, 0.6, 1.1, 1.4, 1.9, 2.3, 2.7, 3.0};
  std::vector<Vec2> pts;
  for (int k = 0; k <= 8; ++k) {
    Vec2 tan = k == 0 ? Vec2(0.9, 0.0)
             : k == 8 ? Vec2(r[8] - r[7], z[8] - z[7])
                      : 0.5 * Vec2(r[k + 1] - r[k - 1], z[k + 1] - z[k - 1]);
    if (k == 4) tan = Vec2(0.0);
    const Vec2 a(r[k], z[k]);
    if (k > 0) pts.push_back(a - tan / 3.0);
    pts.push_back(a);
    if (k < 8) pts.push_back(a + tan / 3.0);
  }
  return pts;
}

std::vector<Family> families() {
  using K = BezierProfileKind;
  return {
      {"cubic vase", {{0.6, 0.0}, {1.6, 0.6}, {0.1, 1.4}, {0.7, 2.0}}, K::SingleCurve},
      {"degree 6",
       {{0.5, 0.0}, {1.2, 0.3}, {0.4, 0.8}, {1.3, 1.2}, {0.2, 1.6}, {0.9, 2.1}, {0.6, 2.5}},
       K::SingleCurve},
      {"8-segment chain", bottle_chain(), K::CubicChain},
      {"non-monotone height",
       {{0.4, 0.0}, {1.6, 0.4}, {1.8, 1.8}, {0.6, 1.9}, {0.3, 0.6}, {1.2, 1.0}},
       K::SingleCurve},
      {"touching axis (sphere-like)",
       {{0, -1}, {0.55, -1}, {1, -0.55}, {1, 0}, {1, 0.55}, {0.55, 1}, {0, 1}},
       K::CubicChain},
      {"touching axis (cone tips)", {{0.0, 1.6}, {0.2, 1.0}, {1.4, 0.2}, {0.0, -0.2}}, K::SingleCurve},
  };
}

struct Transform {
  std::string name;
  Mat4 m;
  double scale;  // world length of a local unit (largest)
};

std::vector<Transform> transforms() {
  const Mat4 I(1.0);
  auto rot = [&](double angle, Vec3 axis) { return glm::rotate(I, angle, glm::normalize(axis)); };
  std::vector<Transform> t;
  t.push_back({"aligned", glm::translate(I, Vec3(0.25, -0.5, 1.0)), 1.0});
  t.push_back({"rotated", glm::translate(I, Vec3(3, -2, 5)) * rot(0.7, Vec3(1, 2, 3)), 1.0});
  t.push_back({"scale 1e-3",
               glm::translate(I, Vec3(2e-3, 1e-3, -4e-3)) * rot(2.1, Vec3(-1, 0.5, 0.2)) *
                   glm::scale(I, Vec3(1e-3)),
               1e-3});
  t.push_back({"scale 1e4",
               glm::translate(I, Vec3(5e4, -3e4, 2e4)) * rot(-1.3, Vec3(0.3, -1, 0.4)) *
                   glm::scale(I, Vec3(1e4)),
               1e4});
  t.push_back({"non-uniform",
               glm::translate(I, Vec3(-1, 4, 2)) * rot(0.9, Vec3(1, -1, 0.5)) *
                   glm::scale(I, Vec3(1.0, 2.5, 0.4)),
               2.5});
  return t;
}

enum class Kind { Sphere, Grazing, Perpendicular, Parallel, ThroughAxis };
const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Sphere: return "sphere";
    case Kind::Grazing: return "grazing";
    case Kind::Perpendicular: return "perpendicular";
    case Kind::Parallel: return "parallel";
    case Kind::ThroughAxis: return "through axis";
  }
  return "";
}

struct LocalBox {  // control-hull bounds of the local profile
  double rmax = 0, zlo = 1e300, zhi = -1e300;
  double radius() const { return std::sqrt(rmax * rmax + 0.25 * (zhi - zlo) * (zhi - zlo)); }
  Vec3 center() const { return Vec3(0, 0, 0.5 * (zlo + zhi)); }
};

Vec3 uniform_sphere(Rng& rng) {
  const double z = 2 * rng.uniform() - 1, phi = 2 * kPi * rng.uniform();
  const double s = std::sqrt(std::max(0.0, 1 - z * z));
  return Vec3(s * std::cos(phi), s * std::sin(phi), z);
}

// A local ray of the given kind (grazing rays are built in world space below).
void local_ray(Kind kind, const LocalBox& b, Rng& rng, Vec3& o, Vec3& d) {
  const double R = b.radius();
  const Vec3 c = b.center();
  switch (kind) {
    case Kind::Sphere: {
      o = c + 1.5 * R * uniform_sphere(rng);
      d = c + R * std::cbrt(rng.uniform()) * uniform_sphere(rng) - o;
      break;
    }
    case Kind::Perpendicular: {
      const double phi = 2 * kPi * rng.uniform();
      d = Vec3(std::cos(phi), std::sin(phi), 0.0);
      const double h = rng.uniform() < 0.25 ? 0.0 : (2 * rng.uniform() - 1) * 1.1 * b.rmax;
      const double z = b.zlo - 0.05 + rng.uniform() * (b.zhi - b.zlo + 0.1);
      o = Vec3(0, 0, z) - 2 * R * d + h * Vec3(-d.y, d.x, 0.0);
      break;
    }
    case Kind::Parallel: {
      const double rr = 1.1 * b.rmax * std::sqrt(rng.uniform()), phi = 2 * kPi * rng.uniform();
      const bool up = rng.uniform() < 0.5;
      d = Vec3(0, 0, up ? 1.0 : -1.0);
      o = Vec3(rr * std::cos(phi), rr * std::sin(phi), up ? b.zlo - R : b.zhi + R);
      break;
    }
    case Kind::ThroughAxis: {
      o = c + 1.5 * R * uniform_sphere(rng);
      d = Vec3(0, 0, b.zlo + rng.uniform() * (b.zhi - b.zlo)) - o;
      break;
    }
    case Kind::Grazing: break;
  }
}

struct Stats {
  long rays = 0, compared = 0, excluded = 0, hits = 0, wrong = 0, nan = 0, bad_normal = 0;
  long bad_uv = 0, foil_wrong = 0, foil_compared = 0, out_of_box = 0;
  double max_rel_t = 0, max_normal = 0;
  void add(const Stats& o) {
    rays += o.rays, compared += o.compared, excluded += o.excluded, hits += o.hits;
    wrong += o.wrong, nan += o.nan, bad_normal += o.bad_normal, bad_uv += o.bad_uv;
    foil_wrong += o.foil_wrong, foil_compared += o.foil_compared, out_of_box += o.out_of_box;
    max_rel_t = std::max(max_rel_t, o.max_rel_t), max_normal = std::max(max_normal, o.max_normal);
  }
};

struct Scene {
  const Family& fam;
  const Transform& tr;
  BezierRevolve surf;
  bezref::Profile prof;
  bezref::M4 to_local;
  bezfoil::Foil foil;
  LocalBox box;
  double world_scale;
  Scene(const Family& f, const Transform& t)
      : fam(f), tr(t), surf(f.pts, f.kind, t.m),
        prof(bezref::make_profile(f.pts, f.kind == BezierProfileKind::CubicChain)),
        to_local(bezref::M4::from_glm(t.m).inverse()),
        foil(bezfoil::make(f.pts, f.kind == BezierProfileKind::CubicChain, t.m)) {
    for (const auto& p : f.pts)
      box.rmax = std::max(box.rmax, std::fabs(p.x)), box.zlo = std::min(box.zlo, p.y),
      box.zhi = std::max(box.zhi, p.y);
    world_scale = box.radius() * t.scale;
  }
};

// What the BVH would do: box test per segment, then the exact test.
bool nearest_hit(const BezierRevolve& s, const Ray& ray, double tmax, Hit& best) {
  const Vec3 inv(1.0 / ray.direction.x, 1.0 / ray.direction.y, 1.0 / ray.direction.z);
  bool found = false;
  for (size_t i = 0; i < s.segment_count(); ++i) {
    if (slab_entry(s.segment_bounds(i), ray.origin, inv, tmax) == kInf) continue;
    Hit h;
    if (s.intersect_segment(i, ray, 0.0, tmax, h)) tmax = h.t, best = h, found = true;
  }
  return found;
}

// A world ray tangent to the surface at a random point, pushed off along the
// normal by one of 0, +-1e-3, +-1e-6, +-1e-9 world scales.
void grazing_ray(const Scene& sc, Rng& rng, long i, Vec3& O, Vec3& D) {
  const auto& prof = sc.prof;
  for (;;) {
    const auto& g = prof.segs[size_t(rng.uniform() * prof.segs.size())];
    const LD t = 0.02 + 0.96 * rng.uniform();
    const double r = double(bezref::casteljau(g.r, g.n, t)), z = double(bezref::casteljau(g.z, g.n, t));
    const double dr = double(bezref::casteljau_d(g.r, g.n, t)), dz = double(bezref::casteljau_d(g.z, g.n, t));
    if (r < 0.05 * double(prof.scale) || std::hypot(dr, dz) < 1e-3) continue;
    const double th = 2 * kPi * rng.uniform(), phi = 2 * kPi * rng.uniform();
    const Vec3 radial(std::cos(th), std::sin(th), 0.0), around(-std::sin(th), std::cos(th), 0.0);
    const Vec3 st = glm::normalize(Vec3(dr * radial.x, dr * radial.y, dz));
    const Vec3 n_local(dz * radial.x, dz * radial.y, -dr);
    const glm::dmat3 l(sc.tr.m);
    const Vec3 P = Vec3(sc.tr.m * glm::dvec4(r * radial.x, r * radial.y, z, 1.0));
    D = glm::normalize(l * (std::cos(phi) * st + std::sin(phi) * around));
    const Vec3 n = glm::normalize(glm::transpose(glm::inverse(l)) * n_local);
    const double offsets[7] = {0, 1e-3, -1e-3, 1e-6, -1e-6, 1e-9, -1e-9};
    O = P + offsets[i % 7] * sc.world_scale * n - 3.0 * sc.world_scale * D;
    return;
  }
}

bool finite_hit(const Hit& h) {
  return std::isfinite(h.t) && is_finite(h.position) && is_finite(h.geometric_normal) &&
         is_finite(h.shading_normal) && std::isfinite(h.uv.x) && std::isfinite(h.uv.y);
}

// Prints a wrong ray in full precision so it can be replayed.
void report_wrong(const Scene& sc, const Vec3& O, const Vec3& D, bool found, const Hit& hit,
                  const bezref::Result& ref) {
  std::printf("WRONG %s / %s: O=(%.17g, %.17g, %.17g) D=(%.17g, %.17g, %.17g) ours %s t=%.17g u=%.17g, "
              "reference %s t=%.17Lg seg %d param %.17Lg cos %.3Lg event %.3Lg\n",
              sc.fam.name.c_str(), sc.tr.name.c_str(), O.x, O.y, O.z, D.x, D.y, D.z,
              found ? "hit" : "miss", hit.t, hit.uv.x, ref.found ? "hit" : "miss", ref.t, ref.seg,
              ref.param, ref.cos, ref.min_event);
}

void check_ray(const Scene& sc, const Vec3& O, const Vec3& D, Stats& st) {
  ++st.rays;
  Hit hit;
  const bool found = nearest_hit(sc.surf, Ray{O, D}, kInf, hit);
  if (found && (!finite_hit(hit) || std::fabs(glm::length(hit.geometric_normal) - 1) > 1e-12 ||
                hit.uv.x < 0 || hit.uv.x > 1 || hit.uv.y < 0 || hit.uv.y >= 1)) {
    ++st.nan;
    return;
  }
  const bezref::Result ref = bezref::intersect(sc.prof, sc.to_local, O, D, 0.0L, 1e300L);
  const bool tangent = ref.min_event < kTouch || (ref.found && ref.normal_valid && ref.cos < kCos);
  if (tangent) {
    ++st.excluded;
    return;
  }
  ++st.compared;
  double foil_t;
  const bool foil_found = bezfoil::intersect(sc.foil, O, D, 0.0, kInf, foil_t);
  ++st.foil_compared;
  if (foil_found != ref.found ||
      (ref.found && std::fabs(foil_t - double(ref.t)) > kTolT * sc.world_scale))
    ++st.foil_wrong;
  const double rel = found && ref.found ? std::fabs(hit.t - double(ref.t)) / sc.world_scale : 0.0;
  if (found != ref.found || rel > kTolT) {
    ++st.wrong;
    report_wrong(sc, O, D, found, hit, ref);
    return;
  }
  if (!found) return;
  ++st.hits;
  st.max_rel_t = std::max(st.max_rel_t, rel);
  if (ref.normal_valid) {
    const Vec3 rn(double(ref.normal.x), double(ref.normal.y), double(ref.normal.z));
    const double dev = 1 - glm::dot(rn, hit.geometric_normal);
    st.max_normal = std::max(st.max_normal, dev);
    if (dev > 1e-8) ++st.bad_normal;
    const double u = (ref.seg + double(ref.param)) / double(sc.prof.segs.size());
    if (std::fabs(u - hit.uv.x) > 1e-6) ++st.bad_uv;
  }
  const Aabb& b = sc.surf.segment_bounds(size_t(ref.seg));
  const Vec3 p = O + double(ref.t) * D;
  for (int a = 0; a < 3; ++a)
    if (p[a] < b.lo[a] || p[a] > b.hi[a]) ++st.out_of_box;
}

long rays_per_case() {
  const char* s = std::getenv("PPM_STRESS");
  return s && std::string(s) == "1" ? 6700 : test_samples(80);  // x 6 families x 5 transforms x 5 kinds (1.005e6 rays under stress)
}

void print_row(const std::string& name, const Stats& s) {
  std::printf("%-30s rays %7ld compared %7ld excluded %5ld hits %7ld | ours wrong %ld (max |dt|/scale %.2e, "
              "max 1-n.n_ref %.1e, bad normal %ld, bad uv %ld, NaN %ld, out of box %ld) | foil wrong %ld "
              "(%.3f%%)\n",
              name.c_str(), s.rays, s.compared, s.excluded, s.hits, s.wrong, s.max_rel_t, s.max_normal,
              s.bad_normal, s.bad_uv, s.nan, s.out_of_box, s.foil_wrong,
              s.foil_compared ? 100.0 * s.foil_wrong / s.foil_compared : 0.0);
}

// ---- Analytic cases -------------------------------------------------------

bool hit_segments(const BezierRevolve& s, const Vec3& o, const Vec3& d, Hit& h, double tmin = 0.0,
                  double tmax = kInf) {
  bool found = false;
  for (size_t i = 0; i < s.segment_count(); ++i) {
    Hit x;
    if (s.intersect_segment(i, Ray{o, glm::normalize(d)}, tmin, tmax, x)) tmax = x.t, h = x, found = true;
  }
  return found;
}

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

std::string error_of(std::vector<Vec2> pts, BezierProfileKind kind, const Mat4& m = Mat4(1.0)) {
  try {
    BezierRevolve s(std::move(pts), kind, m);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(BezierRevolve, ConstructorErrorsNameTheProblem) {
  using K = BezierProfileKind;
  const double nan = std::nan(""), inf = kInf;
  EXPECT_NE(error_of({{0, 0}, {1, 1}, {nan, 2}}, K::SingleCurve).find("point 2 has a non-finite radius"), std::string::npos);
  EXPECT_NE(error_of({{0, 0}, {1, inf}}, K::SingleCurve).find("point 1 has a non-finite height"), std::string::npos);
  EXPECT_NE(error_of({{1, 1}}, K::SingleCurve).find("at least 2 points, got 1"), std::string::npos);
  EXPECT_NE(error_of(std::vector<Vec2>(10, Vec2(1, 0)), K::SingleCurve).find("degree 9"), std::string::npos);
  EXPECT_NE(error_of({{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}, K::CubicChain).find("3k+1"), std::string::npos);
  EXPECT_NE(error_of({{1, 2}, {1, 2}, {1, 2}}, K::SingleCurve).find("identical"), std::string::npos);
  Mat4 singular(1.0);
  singular[2] = glm::dvec4(0.0);
  EXPECT_NE(error_of({{0, 0}, {1, 1}}, K::SingleCurve, singular).find("singular"), std::string::npos);
  Mat4 projective(1.0);
  projective[0][3] = 0.5;
  EXPECT_NE(error_of({{0, 0}, {1, 1}}, K::SingleCurve, projective).find("not affine"), std::string::npos);
  Mat4 bad(1.0);
  bad[3][1] = nan;
  EXPECT_NE(error_of({{0, 0}, {1, 1}}, K::SingleCurve, bad).find("non-finite entry at row 1, column 3"), std::string::npos);
  EXPECT_EQ(error_of(std::vector<Vec2>(9, Vec2(1, 0)), K::SingleCurve).find("degree"), std::string::npos);
}

TEST(BezierRevolve, CylinderFromOutsideAndInside) {
  const BezierRevolve cyl({{1, 0}, {1, 2}}, BezierProfileKind::SingleCurve, Mat4(1.0));
  EXPECT_EQ(cyl.segment_count(), 1u);
  Hit h;
  ASSERT_TRUE(hit_segments(cyl, Vec3(3, 0, 1), Vec3(-1, 0, 0), h));
  EXPECT_DOUBLE_EQ(h.t, 2.0);
  expect_vec(h.geometric_normal, Vec3(1, 0, 0), 1e-15);  // profile goes up: normal away from the axis
  EXPECT_NEAR(h.uv.x, 0.5, 1e-15);
  EXPECT_NEAR(h.uv.y, 0.0, 1e-15);
  ASSERT_TRUE(hit_segments(cyl, Vec3(0, 0, 1), Vec3(0, -1, 0), h));  // from the axis, inside
  EXPECT_NEAR(h.t, 1.0, 1e-15);
  expect_vec(h.geometric_normal, Vec3(0, -1, 0), 1e-15);
  EXPECT_NEAR(h.uv.y, 0.75, 1e-15);
  ASSERT_TRUE(hit_segments(cyl, Vec3(0.5, -3, 1.5), Vec3(0, 1, 0), h));
  EXPECT_NEAR(h.t, 3 - std::sqrt(0.75), 1e-15);
  EXPECT_FALSE(hit_segments(cyl, Vec3(1.0001, -3, 1.5), Vec3(0, 1, 0), h));  // misses by 1e-4
  EXPECT_FALSE(hit_segments(cyl, Vec3(3, 0, 2.0001), Vec3(-1, 0, 0), h));   // above the open end
  EXPECT_FALSE(hit_segments(cyl, Vec3(0.5, 0, -1), Vec3(0, 0, 1), h));      // along the axis inside
  // tmin / tmax: the far wall only, then nothing.
  ASSERT_TRUE(hit_segments(cyl, Vec3(3, 0, 1), Vec3(-1, 0, 0), h, 2.5));
  EXPECT_NEAR(h.t, 4.0, 1e-15);
  EXPECT_FALSE(hit_segments(cyl, Vec3(3, 0, 1), Vec3(-1, 0, 0), h, 0.0, 1.999));
}

TEST(BezierRevolve, DiskThroughTheAxisKeepsItsOrientation) {
  // r from -1 to 1 at z = 0: crosses the axis; r' > 0 so the normal is -z everywhere.
  const BezierRevolve disk({{-1, 0}, {1, 0}}, BezierProfileKind::SingleCurve, Mat4(1.0));
  for (const Vec3& o : {Vec3(0.5, 0, 1), Vec3(-0.3, 0.2, 1), Vec3(0, 0, 1), Vec3(0.1, -0.7, -2)}) {
    Hit h;
    const Vec3 d(0, 0, o.z > 0 ? -1 : 1);
    ASSERT_TRUE(hit_segments(disk, o, d, h)) << o.x << " " << o.y;
    EXPECT_NEAR(h.t, std::fabs(o.z), 1e-15);
    expect_vec(h.geometric_normal, Vec3(0, 0, -1), 1e-15);
  }
}

TEST(BezierRevolve, PolesAndOutwardNormalsOfAClosedProfile) {
  // Counter-clockwise in (r, z): bottom pole -> equator -> top pole.
  const BezierRevolve sph({{0, -1}, {0.55, -1}, {1, -0.55}, {1, 0}, {1, 0.55}, {0.55, 1}, {0, 1}},
                          BezierProfileKind::CubicChain, Mat4(1.0));
  Hit h;
  ASSERT_TRUE(hit_segments(sph, Vec3(0, 0, -5), Vec3(0, 0, 1), h));  // along the axis: the pole
  EXPECT_NEAR(h.t, 4.0, 1e-15);
  expect_vec(h.geometric_normal, Vec3(0, 0, -1), 1e-15);
  EXPECT_NEAR(h.uv.x, 0.0, 1e-15);
  ASSERT_TRUE(hit_segments(sph, Vec3(0, 0, 5), Vec3(0, 0, -1), h));
  EXPECT_NEAR(h.t, 4.0, 1e-15);
  expect_vec(h.geometric_normal, Vec3(0, 0, 1), 1e-15);
  EXPECT_NEAR(h.uv.x, 1.0, 1e-15);
  ASSERT_TRUE(hit_segments(sph, Vec3(-5, 0, 0), Vec3(1, 0, 0), h));  // through the axis, perpendicular
  EXPECT_NEAR(h.t, 4.0, 1e-15);
  expect_vec(h.geometric_normal, Vec3(-1, 0, 0), 1e-15);
  EXPECT_NEAR(h.uv.y, 0.5, 1e-15);
  Rng rng(11, 0, 0);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 o = 3.0 * uniform_sphere(rng), target = 0.9 * uniform_sphere(rng);
    if (!hit_segments(sph, o, target - o, h)) continue;
    ++hits;
    EXPECT_GT(glm::dot(h.geometric_normal, h.position), 0.0);                 // outward
    EXPECT_LT(glm::dot(h.geometric_normal, glm::normalize(target - o)), 0.0);  // faces the ray
  }
  EXPECT_GT(hits, 1900);
}

TEST(BezierRevolve, ConeTipAndCuspGiveFiniteNormals) {
  // Teardrop: cone tips on the axis at both ends.
  const BezierRevolve tear({{0.0, 1.6}, {0.2, 1.0}, {1.4, 0.2}, {0.0, -0.2}}, BezierProfileKind::SingleCurve,
                           Mat4(1.0));
  Hit h;
  ASSERT_TRUE(hit_segments(tear, Vec3(0, 0, 3), Vec3(0, 0, -1), h));
  EXPECT_NEAR(h.t, 1.4, 1e-14);
  EXPECT_TRUE(finite_hit(h));
  EXPECT_NEAR(glm::length(h.geometric_normal), 1.0, 1e-15);
  // Bottle chain: anchor 4 = (0.5, 1.4) has zero-length handles (r' = z' = 0).
  const BezierRevolve bottle(bottle_chain(), BezierProfileKind::CubicChain, Mat4(1.0));
  for (const Vec3& d : {Vec3(-1, 0, 0), Vec3(-1, 0, 0.3), Vec3(-1, 0, -0.3)}) {
    const Vec3 o = Vec3(0.5, 0, 1.4) - 2.0 * glm::normalize(d);
    ASSERT_TRUE(hit_segments(bottle, o, d, h));
    EXPECT_TRUE(finite_hit(h));
    EXPECT_NEAR(glm::length(h.geometric_normal), 1.0, 1e-15);
  }
}

TEST(BezierRevolve, BoundsContainTheSurface) {
  for (const Family& fam : families()) {
    for (const Transform& tr : transforms()) {
      const BezierRevolve s(fam.pts, fam.kind, tr.m);
      const auto prof = bezref::make_profile(fam.pts, fam.kind == BezierProfileKind::CubicChain);
      for (size_t k = 0; k < s.segment_count(); ++k) {
        const Aabb b = s.segment_bounds(k);
        for (int i = 0; i <= 200; ++i) {
          const LD t = LD(i) / 200;
          const double r = double(bezref::casteljau(prof.segs[k].r, prof.segs[k].n, t));
          const double z = double(bezref::casteljau(prof.segs[k].z, prof.segs[k].n, t));
          for (int j = 0; j < 16; ++j) {
            const double th = 2 * kPi * j / 16;
            const Vec3 p = Vec3(tr.m * glm::dvec4(r * std::cos(th), r * std::sin(th), z, 1.0));
            for (int a = 0; a < 3; ++a) {
              EXPECT_GE(p[a], b.lo[a]) << fam.name << " " << tr.name;
              EXPECT_LE(p[a], b.hi[a]) << fam.name << " " << tr.name;
            }
          }
        }
      }
    }
  }
}

TEST(BezierRevolve, MatchesReferenceOnAllFamilies) {
  const long n = rays_per_case();
  const Kind kinds[5] = {Kind::Sphere, Kind::Grazing, Kind::Perpendicular, Kind::Parallel, Kind::ThroughAxis};
  Stats total;
  Stats per_kind[5];
  for (const Family& fam : families()) {
    Stats fs;
    for (const Transform& tr : transforms()) {
      const Scene sc(fam, tr);
      const glm::dmat3 l(tr.m);
      for (int k = 0; k < 5; ++k) {
        Rng rng(7, uint64_t(k), std::hash<std::string>()(fam.name + tr.name));
        Stats ks;
        for (long i = 0; i < n; ++i) {
          Vec3 O, D;
          if (kinds[k] == Kind::Grazing) {
            grazing_ray(sc, rng, i, O, D);
          } else {
            Vec3 o(0.0), d(0.0, 0.0, 1.0);
            local_ray(kinds[k], sc.box, rng, o, d);
            O = Vec3(tr.m * glm::dvec4(o, 1.0));
            D = glm::normalize(l * d);
          }
          check_ray(sc, O, D, ks);
        }
        per_kind[k].add(ks);
        fs.add(ks);
      }
    }
    print_row(fam.name, fs);
    total.add(fs);
    EXPECT_EQ(fs.wrong, 0) << fam.name;
    EXPECT_EQ(fs.nan, 0) << fam.name;
    EXPECT_EQ(fs.bad_normal, 0) << fam.name;
    EXPECT_EQ(fs.bad_uv, 0) << fam.name;
    EXPECT_EQ(fs.out_of_box, 0) << fam.name;
    EXPECT_GT(fs.hits, fs.compared / 10) << fam.name;
  }
  for (int k = 0; k < 5; ++k) print_row(std::string("  kind: ") + kind_name(kinds[k]), per_kind[k]);
  print_row("TOTAL", total);
  EXPECT_LT(total.excluded, total.rays / 10);
}

}  // namespace
