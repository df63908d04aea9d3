// The microfiber sheen (see microfiber_sheen.h).
#include "shading/microfiber_sheen.h"

#include "math/sampling.h"

#include <algorithm>
#include <cmath>

namespace ppm {
namespace {

struct SheenLtc {
  float a, b, albedo;
};
constexpr int kSteps = 32;
constexpr SheenLtc kTable[kSteps * kSteps] = {  // [roughness][mu], both 0 to 1
#include "shading/sheen_ltc_table.inc"
};

// Bilinear in the table (its first row and column hold the fits at 0.01), as Cycles reads it.
SheenLtc lookup(double roughness, double mu) {
  const double x = glm::clamp(mu, 0.0, 1.0) * (kSteps - 1), y = glm::clamp(roughness, 1e-3, 1.0) * (kSteps - 1);
  const int i = std::min(static_cast<int>(x), kSteps - 2), j = std::min(static_cast<int>(y), kSteps - 2);
  const double tx = x - i, ty = y - j;
  auto at = [](int row, int col) { return kTable[row * kSteps + col]; };
  auto mix = [&](float SheenLtc::*field) {
    const double low = (1.0 - tx) * at(j, i).*field + tx * at(j, i + 1).*field;
    const double high = (1.0 - tx) * at(j + 1, i).*field + tx * at(j + 1, i + 1).*field;
    return (1.0 - ty) * low + ty * high;
  };
  return {static_cast<float>(mix(&SheenLtc::a)), static_cast<float>(mix(&SheenLtc::b)),
          static_cast<float>(mix(&SheenLtc::albedo))};
}

// The frame of a viewer: n on its side, x towards it along the surface.
struct ViewFrame {
  Vec3 x, y, n;
  double mu;
};
ViewFrame view_frame(const SurfacePoint& sp, const Vec3& view) {
  const Vec3 n = glm::dot(view, sp.ng) >= 0.0 ? sp.ns : -sp.ns;
  const double mu = glm::dot(view, n);
  Vec3 x = view - n * mu;
  const double length = glm::length(x);
  if (length > 1e-9) {
    x /= length;
  } else {
    Vec3 unused;
    make_basis(n, x, unused);
  }
  return {x, glm::cross(n, x), n, mu};
}

bool usable(const SheenLtc& ltc) { return std::fabs(ltc.a) > 1e-5f && ltc.albedo > 1e-5f; }

// R D(...) |M^-1| / |M^-1 l|^3 for l in the viewer's frame: f cos(theta_l) / color.
double cosine_weighted(const SheenLtc& ltc, const Vec3& l) {
  const Vec3 m(ltc.a * l.x + ltc.b * l.z, ltc.a * l.y, l.z);
  const double length = glm::length(m);
  if (!(l.z > 0.0 && length > 0.0)) return 0.0;
  return ltc.albedo * kInvPi * (l.z / length) * (ltc.a * ltc.a) / (length * length * length);
}

// f(view, light) cos(light) / color, both directions on the side of sp.ng given by view.
double sheen_cosine_weighted(double roughness, const SurfacePoint& sp, const Vec3& view, const Vec3& light) {
  if (glm::dot(view, sp.ng) * glm::dot(light, sp.ng) <= 0.0) return 0.0;
  const ViewFrame f = view_frame(sp, view);
  if (!(f.mu > 0.0)) return 0.0;
  const SheenLtc ltc = lookup(roughness, f.mu);
  if (!usable(ltc)) return 0.0;
  return cosine_weighted(ltc, Vec3(glm::dot(light, f.x), glm::dot(light, f.y), glm::dot(light, f.n)));
}

}  // namespace

double microfiber_sheen_albedo(double roughness, double mu) {
  const SheenLtc ltc = lookup(roughness, mu);
  return usable(ltc) ? ltc.albedo : 0.0;
}

Color microfiber_sheen_eval(const Color& color, double roughness, const SurfacePoint& sp, const Vec3& wo,
                            const Vec3& wi) {
  const double cos_i = std::fabs(glm::dot(wi, sp.ns));
  if (!(cos_i > 0.0)) return Color(0.0);
  return color * (sheen_cosine_weighted(roughness, sp, wo, wi) / cos_i);
}

bool microfiber_sheen_sample(const Color& color, double roughness, const SurfacePoint& sp, const Vec3& wo,
                             double u1, double u2, bool photon, BsdfSample& out) {
  const ViewFrame f = view_frame(sp, wo);
  if (!(f.mu > 0.0)) return false;
  const SheenLtc ltc = lookup(roughness, f.mu);
  if (!usable(ltc)) return false;
  // M maps the cosine-distributed direction: M = [[1/a, 0, -b/a], [0, 1/a, 0], [0, 0, 1]].
  const Vec3 c = sample_cosine_hemisphere(u1, u2);
  const Vec3 l = glm::normalize(Vec3((c.x - ltc.b * c.z) / ltc.a, c.y / ltc.a, c.z));
  out.wi = l.x * f.x + l.y * f.y + l.z * f.n;
  if (glm::dot(out.wi, sp.ng) * glm::dot(wo, sp.ng) <= 0.0) return false;  // the shading normal's far side
  out.specular = false;
  out.ray_kind = kDiffuseRay;
  if (!photon) {
    out.weight = color * static_cast<double>(ltc.albedo);
    return true;
  }
  // Sampled as seen from wo, pdf = f(wo, wi) cos(wi) / (color R); a photon weighs f(wi, wo) cos(wi) / pdf.
  const double pdf = cosine_weighted(ltc, l) / ltc.albedo;
  const double cos_o = std::fabs(glm::dot(wo, sp.ns));
  if (!(pdf > 0.0 && cos_o > 0.0)) return false;
  const double adjoint = sheen_cosine_weighted(roughness, sp, out.wi, wo) / cos_o * std::fabs(glm::dot(out.wi, sp.ns));
  out.weight = color * (adjoint / pdf);
  return adjoint > 0.0;
}

}  // namespace ppm
