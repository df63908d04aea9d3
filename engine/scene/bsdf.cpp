// BSDF evaluation and sampling (see bsdf.h). Microfacet lobes use GGX with
// visible-normal sampling (Heitz 2018) and the Smith height-correlated masking;
// rough refraction follows Walter et al. 2007.
#include "scene/bsdf.h"

#include "math/sampling.h"

namespace ppm {
namespace {

Vec3 reflect(const Vec3& w, const Vec3& n) { return 2.0 * glm::dot(w, n) * n - w; }

// Refracts w (pointing away, on n's side) through a surface with relative index
// eta = eta_i / eta_t. False on total internal reflection.
bool refract(const Vec3& w, const Vec3& n, double eta, Vec3& out) {
  const double cos_i = glm::dot(w, n);
  const double sin2_t = eta * eta * std::fmax(0.0, 1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return false;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  out = glm::normalize(-eta * w + (eta * cos_i - cos_t) * n);
  return true;
}

Color schlick(const Color& f0, double mu) {
  const double m = std::fmax(0.0, 1.0 - mu), m5 = m * m * m * m * m;
  return f0 + (Color(1.0) - f0) * m5;
}

// Conductor Fresnel: Schlick with the F82-tint correction (Hoffman 2023), as
// Blender's Principled BSDF uses for metals.
Color conductor_fresnel(const Color& f0, const Color& tint, double mu) {
  constexpr double mu_bar = 1.0 / 7.0;
  const double denom = mu_bar * std::pow(1.0 - mu_bar, 6.0);
  const Color f_bar = schlick(f0, mu_bar);
  const Color a = f_bar * (Color(1.0) - tint) / denom;
  const Color f = schlick(f0, mu) - a * mu * std::pow(std::fmax(0.0, 1.0 - mu), 6.0);
  return glm::clamp(f, 0.0, 1.0);
}

// --- GGX in a local frame where the normal is +Z ---
double ggx_d(const Vec3& h, double a2) {
  if (h.z <= 0.0) return 0.0;
  const double c2 = h.z * h.z;
  const double d = c2 * (a2 - 1.0) + 1.0;
  return a2 / (kPi * d * d);
}
double ggx_lambda(const Vec3& w, double a2) {
  const double c2 = w.z * w.z;
  if (c2 <= 0.0) return kInf;
  const double t2 = std::fmax(0.0, 1.0 - c2) / c2;
  return 0.5 * (-1.0 + std::sqrt(1.0 + a2 * t2));
}
double ggx_g1(const Vec3& w, double a2) { return 1.0 / (1.0 + ggx_lambda(w, a2)); }
double ggx_g2(const Vec3& wo, const Vec3& wi, double a2) {
  return 1.0 / (1.0 + ggx_lambda(wo, a2) + ggx_lambda(wi, a2));
}
// Visible normal sampling (Heitz 2018); wo.z > 0.
Vec3 ggx_sample_vndf(const Vec3& wo, double alpha, double u1, double u2) {
  const Vec3 vh = glm::normalize(Vec3(alpha * wo.x, alpha * wo.y, wo.z));
  const double len2 = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = len2 > 0.0 ? Vec3(-vh.y, vh.x, 0.0) / std::sqrt(len2) : Vec3(1.0, 0.0, 0.0);
  const Vec3 t2 = glm::cross(vh, t1);
  const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
  const double p1 = r * std::cos(phi);
  double p2 = r * std::sin(phi);
  const double s = 0.5 * (1.0 + vh.z);
  p2 = (1.0 - s) * std::sqrt(std::fmax(0.0, 1.0 - p1 * p1)) + s * p2;
  const Vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::fmax(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(Vec3(alpha * nh.x, alpha * nh.y, std::fmax(1e-12, nh.z)));
}

struct LocalFrame {
  Vec3 t, b, n;
  Vec3 to_local(const Vec3& v) const { return Vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)); }
  Vec3 to_world(const Vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};
LocalFrame frame_of(const Vec3& n) {
  LocalFrame f;
  f.n = n;
  make_basis(n, f.t, f.b);
  return f;
}

// Side-aware quantities for dielectrics: the normal facing wo and the indices.
struct DielectricSide {
  Vec3 n;             // shading normal on wo's side
  double eta_o, eta_i;  // index on wo's side and on the far side
};
DielectricSide dielectric_side(const Material& m, const SurfacePoint& sp, const Vec3& wo) {
  const bool outside = glm::dot(wo, sp.ng) >= 0.0;
  return outside ? DielectricSide{sp.ns, 1.0, m.ior} : DielectricSide{-sp.ns, m.ior, 1.0};
}

Color eval_rough_metal(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  const Vec3 n = glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns;
  const LocalFrame f = frame_of(n);
  const Vec3 lo = f.to_local(wo), li = f.to_local(wi);
  if (lo.z <= 0.0 || li.z <= 0.0) return Color(0.0);
  const double a = m.roughness * m.roughness, a2 = a * a;
  const Vec3 h = glm::normalize(lo + li);
  return conductor_fresnel(sp.albedo, m.specular_tint, glm::dot(lo, h)) * ggx_d(h, a2) *
         ggx_g2(lo, li, a2) / (4.0 * lo.z * li.z);
}

Color eval_rough_glass(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  const DielectricSide s = dielectric_side(m, sp, wo);
  const LocalFrame f = frame_of(s.n);
  const Vec3 lo = f.to_local(wo), li = f.to_local(wi);
  if (lo.z <= 0.0 || li.z == 0.0) return Color(0.0);
  const double a = m.roughness * m.roughness, a2 = a * a;
  if (li.z > 0.0) {  // reflection
    const Vec3 h = glm::normalize(lo + li);
    const double F = fresnel_dielectric(glm::dot(lo, h), s.eta_o, s.eta_i);
    return Color(F * ggx_d(h, a2) * ggx_g2(lo, li, a2) / (4.0 * lo.z * li.z));
  }
  // Transmission (Walter 2007, eq. 21, radiance form with wi the light side).
  Vec3 h = -(s.eta_o * lo + s.eta_i * li);
  if (glm::dot(h, h) == 0.0) return Color(0.0);
  h = glm::normalize(h);
  if (h.z < 0.0) h = -h;
  const double oh = glm::dot(lo, h), ih = glm::dot(li, h);
  if (oh <= 0.0 || ih >= 0.0) return Color(0.0);
  const double F = fresnel_dielectric(oh, s.eta_o, s.eta_i);
  const double denom = s.eta_i * ih + s.eta_o * oh;
  const Vec3 li_up(li.x, li.y, -li.z);
  const double value = std::fabs(ih) * oh * s.eta_o * s.eta_o * (1.0 - F) * ggx_d(h, a2) *
                       ggx_g2(lo, li_up, a2) / (lo.z * std::fabs(li.z) * denom * denom);
  return m.base_color * value;
}

bool sample_rough(const Material& m, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                  double u3, BsdfSample& out) {
  const bool glass = m.kind == MaterialKind::Glass;
  const DielectricSide s = glass ? dielectric_side(m, sp, wo)
                                 : DielectricSide{glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns, 1.0, 1.0};
  const LocalFrame f = frame_of(s.n);
  const Vec3 lo = f.to_local(wo);
  if (lo.z <= 0.0) return false;
  const double a = std::fmax(m.roughness * m.roughness, 1e-4), a2 = a * a;
  const Vec3 h = ggx_sample_vndf(lo, a, u1, u2);
  const double oh = glm::dot(lo, h);
  if (oh <= 0.0) return false;
  out.specular = false;
  if (!glass) {
    const Vec3 li = reflect(lo, h);
    if (li.z <= 0.0) return false;
    out.wi = f.to_world(li);
    out.weight = conductor_fresnel(sp.albedo, m.specular_tint, oh) * (ggx_g2(lo, li, a2) / ggx_g1(lo, a2));
    return true;
  }
  const double F = fresnel_dielectric(oh, s.eta_o, s.eta_i);
  Vec3 li;
  if (u3 < F || !refract(lo, h, s.eta_o / s.eta_i, li)) {
    li = reflect(lo, h);
    if (li.z <= 0.0) return false;
    out.weight = Color(ggx_g2(lo, li, a2) / ggx_g1(lo, a2));
  } else {
    if (li.z >= 0.0) return false;
    out.weight = m.base_color * (ggx_g2(lo, Vec3(li.x, li.y, -li.z), a2) / ggx_g1(lo, a2));
  }
  out.wi = f.to_world(li);
  return true;
}

}  // namespace

double fresnel_dielectric(double cos_i, double eta_i, double eta_t) {
  cos_i = glm::clamp(cos_i, 0.0, 1.0);
  const double sin_t = eta_i / eta_t * std::sqrt(std::fmax(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(std::fmax(0.0, 1.0 - sin_t * sin_t));
  const double rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  const double rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

Color bsdf_eval(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  switch (m.kind) {
    case MaterialKind::Diffuse: {
      // Reflection only: wo and wi on the same geometric side.
      const double so = glm::dot(wo, sp.ng), si = glm::dot(wi, sp.ng);
      if (so * si <= 0.0) return Color(0.0);
      return sp.albedo * kInvPi;
    }
    case MaterialKind::Metal:
      return m.roughness < kSmoothRoughness ? Color(0.0) : eval_rough_metal(m, sp, wo, wi);
    case MaterialKind::Glass:
      return m.roughness < kSmoothRoughness ? Color(0.0) : eval_rough_glass(m, sp, wo, wi);
    case MaterialKind::Mirror:
    case MaterialKind::Emission:
    case MaterialKind::Holdout:
      return Color(0.0);
  }
  return Color(0.0);
}

bool bsdf_sample(const Material& m, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                 double u3, BsdfSample& out) {
  switch (m.kind) {
    case MaterialKind::Diffuse: {
      const Vec3 n = glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns;
      out.wi = to_world(sample_cosine_hemisphere(u1, u2), n);
      const double side = glm::dot(out.wi, sp.ng) * glm::dot(wo, sp.ng);
      if (side <= 0.0) return false;  // shading normal pushed the sample below the surface
      out.weight = sp.albedo;
      out.specular = false;
      return true;
    }
    case MaterialKind::Mirror:
    case MaterialKind::Metal:
    case MaterialKind::Glass: {
      if (m.roughness >= kSmoothRoughness && m.kind != MaterialKind::Mirror)
        return sample_rough(m, sp, wo, u1, u2, u3, out);
      BsdfSample branches[2];
      const int count = specular_branches(m, sp, wo, branches);
      if (count == 0) return false;
      if (count == 1) {
        out = branches[0];
        return true;
      }
      // Choose by the branches' weights, then divide by the choice probability.
      const double w0 = luminance(branches[0].weight), w1 = luminance(branches[1].weight);
      const double p0 = w0 + w1 > 0.0 ? w0 / (w0 + w1) : 0.5;
      if (u3 < p0) {
        out = branches[0];
        out.weight /= p0;
      } else {
        out = branches[1];
        out.weight /= (1.0 - p0);
      }
      return true;
    }
    case MaterialKind::Emission:
    case MaterialKind::Holdout:
      return false;
  }
  return false;
}

int specular_branches(const Material& m, const SurfacePoint& sp, const Vec3& wo, BsdfSample out[2]) {
  switch (m.kind) {
    case MaterialKind::Mirror:
    case MaterialKind::Metal: {
      const Vec3 n = glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns;
      const double mu = glm::dot(wo, n);
      if (mu <= 0.0) return 0;
      out[0].wi = reflect(wo, n);
      out[0].weight = m.kind == MaterialKind::Mirror ? sp.albedo
                                                     : conductor_fresnel(sp.albedo, m.specular_tint, mu);
      out[0].specular = true;
      return 1;
    }
    case MaterialKind::Glass: {
      const DielectricSide s = dielectric_side(m, sp, wo);
      const double mu = glm::dot(wo, s.n);
      if (mu <= 0.0) return 0;
      const double F = fresnel_dielectric(mu, s.eta_o, s.eta_i);
      out[0].wi = reflect(wo, s.n);
      out[0].weight = Color(F);
      out[0].specular = true;
      Vec3 t;
      if (F >= 1.0 || !refract(wo, s.n, s.eta_o / s.eta_i, t)) {
        out[0].weight = Color(1.0);
        return 1;
      }
      out[1].wi = t;
      out[1].weight = (1.0 - F) * m.base_color;
      out[1].specular = true;
      return 2;
    }
    default:
      return 0;
  }
}

}  // namespace ppm
