// The GGX microfacet distribution with Smith height-correlated masking, visible-normal sampling
// (Heitz 2018), Beckmann's (Blender's other), and the Fresnel terms of dielectrics and conductors.
// Local frames have the normal along +Z.
#pragma once

#include "math/types.h"

#include <cmath>

namespace ppm {

inline Vec3 reflect(const Vec3& w, const Vec3& n) { return 2.0 * glm::dot(w, n) * n - w; }

// Refracts w (pointing away, on n's side) through a surface with relative index
// eta = eta_i / eta_t. False on total internal reflection.
inline bool refract(const Vec3& w, const Vec3& n, double eta, Vec3& out) {
  const double cos_i = glm::dot(w, n);
  const double sin2_t = eta * eta * std::fmax(0.0, 1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return false;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  out = glm::normalize(-eta * w + (eta * cos_i - cos_t) * n);
  return true;
}

// Fresnel reflectance of a dielectric for cos_i on the side with index eta_i.
inline double fresnel_dielectric(double cos_i, double eta_i, double eta_t) {
  cos_i = glm::clamp(cos_i, 0.0, 1.0);
  const double sin_t = eta_i / eta_t * std::sqrt(std::fmax(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(std::fmax(0.0, 1.0 - sin_t * sin_t));
  const double rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  const double rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

inline Color schlick(const Color& f0, double mu) {
  const double m = std::fmax(0.0, 1.0 - mu), m5 = m * m * m * m * m;
  return f0 + (Color(1.0) - f0) * m5;
}

// Conductor Fresnel: Schlick with the F82-tint correction (Hoffman 2023), as
// Blender's Principled BSDF uses for metals.
inline Color conductor_fresnel(const Color& f0, const Color& tint, double mu) {
  constexpr double mu_bar = 1.0 / 7.0;
  const double denom = mu_bar * std::pow(1.0 - mu_bar, 6.0);
  const Color f_bar = schlick(f0, mu_bar);
  const Color a = f_bar * (Color(1.0) - tint) / denom;
  const Color f = schlick(f0, mu) - a * mu * std::pow(std::fmax(0.0, 1.0 - mu), 6.0);
  return glm::clamp(f, 0.0, 1.0);
}

inline double ggx_d(const Vec3& h, double a2) {
  if (h.z <= 0.0) return 0.0;
  const double c2 = h.z * h.z;
  const double d = c2 * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}
inline double ggx_lambda(const Vec3& w, double a2) {
  const double c2 = w.z * w.z;
  if (c2 <= 0.0) return kInf;
  const double t2 = std::fmax(0.0, 1.0 - c2) / c2;
  return 0.5 * (-1.0 + std::sqrt(1.0 + a2 * t2));
}
inline double ggx_g1(const Vec3& w, double a2) { return 1.0 / (1.0 + ggx_lambda(w, a2)); }
inline double ggx_g2(const Vec3& wo, const Vec3& wi, double a2) {
  return 1.0 / (1.0 + ggx_lambda(wo, a2) + ggx_lambda(wi, a2));
}

// Anisotropic GGX, alpha_x along the local x axis (the tangent), alpha_y along y.
inline double ggx_d(const Vec3& h, double ax, double ay) {
  if (h.z <= 0.0) return 0.0;
  const double x = h.x / ax, y = h.y / ay, d = x * x + y * y + h.z * h.z;
  return 1.0 / (kPi * ax * ay * d * d);
}
inline double ggx_lambda(const Vec3& w, double ax, double ay) {
  const double c2 = w.z * w.z;
  if (c2 <= 0.0) return kInf;
  return 0.5 * (-1.0 + std::sqrt(1.0 + (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / c2));
}
inline double ggx_g1(const Vec3& w, double ax, double ay) { return 1.0 / (1.0 + ggx_lambda(w, ax, ay)); }
inline double ggx_g2(const Vec3& wo, const Vec3& wi, double ax, double ay) {
  return 1.0 / (1.0 + ggx_lambda(wo, ax, ay) + ggx_lambda(wi, ax, ay));
}

// Visible normal sampling (Heitz 2018), anisotropic; wo.z > 0.
inline Vec3 ggx_sample_vndf(const Vec3& wo, double ax, double ay, double u1, double u2) {
  const Vec3 vh = glm::normalize(Vec3(ax * wo.x, ay * wo.y, wo.z));
  const double len2 = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = len2 > 0.0 ? Vec3(-vh.y, vh.x, 0.0) / std::sqrt(len2) : Vec3(1.0, 0.0, 0.0);
  const Vec3 t2 = glm::cross(vh, t1);
  const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
  const double p1 = r * std::cos(phi);
  double p2 = r * std::sin(phi);
  const double s = 0.5 * (1.0 + vh.z);
  p2 = (1.0 - s) * std::sqrt(std::fmax(0.0, 1.0 - p1 * p1)) + s * p2;
  const Vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::fmax(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(Vec3(ax * nh.x, ay * nh.y, std::fmax(1e-12, nh.z)));
}
inline Vec3 ggx_sample_vndf(const Vec3& wo, double alpha, double u1, double u2) {
  return ggx_sample_vndf(wo, alpha, alpha, u1, u2);
}

// Beckmann's distribution, anisotropic as GGX above, with Smith's masking through Walter et al.'s
// rational approximation of Lambda (as Cycles: zero for a >= 1.6).
inline double beckmann_d(const Vec3& h, double ax, double ay) {
  if (h.z <= 0.0) return 0.0;
  const double c2 = h.z * h.z, x = h.x / ax, y = h.y / ay;
  return std::exp(-(x * x + y * y) / c2) / (kPi * ax * ay * c2 * c2);
}
inline double beckmann_lambda(const Vec3& w, double ax, double ay) {
  const double c2 = w.z * w.z;
  if (c2 <= 0.0) return kInf;
  const double t2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / c2;  // (alpha tan(theta))^2
  if (t2 < 0.39) return 0.0;                                             // a = 1 / sqrt(t2) > 1.6
  const double a = 1.0 / std::sqrt(t2);
  return ((0.396 * a - 1.259) * a + 1.0) / ((2.181 * a + 3.535) * a);
}
// A Beckmann normal drawn with density D(h) h.z: Gaussian slopes.
inline Vec3 beckmann_sample_d_cos(double ax, double ay, double u1, double u2) {
  const double r = std::sqrt(-std::log(std::fmax(1.0 - u1, 1e-300))), phi = 2.0 * kPi * u2;
  return glm::normalize(Vec3(-ax * r * std::cos(phi), -ay * r * std::sin(phi), 1.0));
}

// One of the two distributions with its alphas along the local x (tangent) and y axes.
struct Microfacet {
  double ax, ay;
  bool beckmann = false;

  double d(const Vec3& h) const { return beckmann ? beckmann_d(h, ax, ay) : ggx_d(h, ax, ay); }
  double lambda(const Vec3& w) const { return beckmann ? beckmann_lambda(w, ax, ay) : ggx_lambda(w, ax, ay); }
  double g2(const Vec3& wo, const Vec3& wi) const { return 1.0 / (1.0 + lambda(wo) + lambda(wi)); }
  // A normal to scatter wo (wo.z > 0) by: GGX's visible normals, Beckmann's by D cos.
  Vec3 sample(const Vec3& wo, double u1, double u2) const {
    return beckmann ? beckmann_sample_d_cos(ax, ay, u1, u2) : ggx_sample_vndf(wo, ax, ay, u1, u2);
  }
  // The density of `sample`'s normals at h (for wo).
  double pdf(const Vec3& wo, const Vec3& h) const {
    if (h.z <= 0.0) return 0.0;
    if (beckmann) return d(h) * h.z;
    return std::fmax(glm::dot(wo, h), 0.0) * d(h) / ((1.0 + lambda(wo)) * wo.z);
  }
  // f |cos| / pdf of a direction scattered through a sampled h, Fresnel aside; wi_up is the
  // direction mirrored into wo's hemisphere (for refraction).
  double sample_weight(const Vec3& wo, const Vec3& wi_up, const Vec3& h) const {
    const double g = g2(wo, wi_up);
    return beckmann ? g * std::fabs(glm::dot(wo, h)) / (wo.z * h.z) : g * (1.0 + lambda(wo));
  }
};

struct LocalFrame {
  Vec3 t, b, n;
  explicit LocalFrame(const Vec3& normal) : n(normal) { make_basis(normal, t, b); }
  // With t along `tangent` made orthogonal to the normal (any basis if it is parallel or zero).
  LocalFrame(const Vec3& normal, const Vec3& tangent) : n(normal) {
    const Vec3 along = tangent - normal * glm::dot(normal, tangent);
    const double len = glm::length(along);
    if (!(len > 1e-9)) {
      make_basis(normal, t, b);
      return;
    }
    t = along / len;
    b = glm::cross(normal, t);
  }
  Vec3 to_local(const Vec3& v) const { return Vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); }
  Vec3 to_world(const Vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

}  // namespace ppm
