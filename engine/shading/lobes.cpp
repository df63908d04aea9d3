// The lobe families' scattering functions (see lobes.h).
#include "shading/lobes.h"

#include "math/sampling.h"
#include "shading/microfacet.h"

namespace ppm {
namespace {

Vec3 facing_normal(const SurfacePoint& sp, const Vec3& wo) { return glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns; }

// Side-aware quantities for dielectrics: the normal facing wo and the indices.
struct DielectricSide {
  Vec3 n;               // shading normal on wo's side
  double eta_o, eta_i;  // index on wo's side and on the far side
};
// A reflection-only dielectric (a specular layer, a coat) is seen from outside on either side, as
// in Cycles: only a surface that refracts has an inside.
DielectricSide dielectric_side(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo) {
  const bool outside = glm::dot(wo, sp.ng) >= 0.0;
  if (p.parts == kReflection) return DielectricSide{outside ? sp.ns : -sp.ns, 1.0, p.ior};
  return outside ? DielectricSide{sp.ns, 1.0, p.ior} : DielectricSide{-sp.ns, p.ior, 1.0};
}

double alpha_of(double roughness) { return roughness * roughness; }

// The microfacet normal h (towards wo's side) that refracts lo into li (local frame, Walter 2007),
// with lo.h and li.h; false where there is none (li on lo's side of h, or no direction at all).
bool refraction_half_vector(const DielectricSide& s, const Vec3& lo, const Vec3& li, Vec3& h, double& oh, double& ih) {
  h = -(s.eta_o * lo + s.eta_i * li);
  if (glm::dot(h, h) == 0.0) return false;
  h = glm::normalize(h);
  if (h.z < 0.0) h = -h;
  oh = glm::dot(lo, h);
  ih = glm::dot(li, h);
  return oh > 0.0 && ih < 0.0;
}

Microfacet dielectric_microfacet(const DielectricParams& p) {
  const double a = std::fmax(alpha_of(p.roughness), 1e-4);
  return {a, a, p.beckmann};
}

Color reflectance(const ConductorParams& p, double mu) { return p.constant ? p.f0 : conductor_fresnel(p.f0, p.f82, mu); }

}  // namespace

Color lambert_eval(const Color& color, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi, bool far_side) {
  const double so = glm::dot(wo, sp.ng), si = glm::dot(wi, sp.ng);
  if (far_side ? so * si >= 0.0 : so * si <= 0.0) return Color(0.0);
  // Nor below the shading normal's horizon (as Cycles): a normal map tilts it away from the geometry's.
  const double sn = glm::dot(wi, facing_normal(sp, wo));
  if (far_side ? sn >= 0.0 : sn <= 0.0) return Color(0.0);
  return color * kInvPi;
}

bool lambert_sample(const Color& color, const SurfacePoint& sp, const Vec3& wo, double u1, double u2, bool far_side,
                    BsdfSample& out) {
  const Vec3 n = far_side ? -facing_normal(sp, wo) : facing_normal(sp, wo);
  out.wi = to_world(sample_cosine_hemisphere(u1, u2), n);
  const double side = glm::dot(out.wi, sp.ng) * glm::dot(wo, sp.ng);
  if (far_side ? side >= 0.0 : side <= 0.0) return false;  // the shading normal pushed it to the wrong side
  out.weight = color;
  out.specular = false;
  out.ray_kind = kDiffuseRay;
  return true;
}

namespace {

// The Oren-Nayar model's directional albedo for white (a pi + b G(cos theta)), G as Fujii derives it.
double oren_nayar_g(double cos_theta) {
  if (cos_theta < 1e-6) return (kPi / 2.0 - 2.0 / 3.0) - cos_theta;  // tan(theta) misbehaves: its series
  const double sin_theta = std::sqrt(std::fmax(0.0, 1.0 - cos_theta * cos_theta));
  const double theta = std::acos(glm::clamp(cos_theta, -1.0, 1.0));
  return sin_theta * (theta - 2.0 / 3.0 - sin_theta * cos_theta) +
         2.0 / 3.0 * (sin_theta / cos_theta) * (1.0 - sin_theta * sin_theta * sin_theta);
}

// f / color at unit cosines nl, nv (both >= 0) and l.v.
Color oren_nayar_shape(const OrenNayarParams& p, double nl, double nv, double lv) {
  const double sigma = glm::clamp(p.sigma, 0.0, 1.0);
  const double a = 1.0 / (kPi + sigma * (kPi / 2.0 - 2.0 / 3.0)), b = sigma * a;
  double t = lv - nl * nv;
  if (t > 0.0) t /= std::fmax(nl, nv) + 1e-300;
  Color f(a + b * t);
  if (p.multiscatter) {
    // Energy compensation: the single-scattering energy E(mu) = a pi + b G(mu) is lost (1 - E) on
    // each side; E_avg its cosine-weighted mean.
    const Color albedo = glm::clamp(p.color, 0.0, 1.0);
    const double e_avg = a * kPi + (2.0 * kPi - 5.6) / 3.0 * b;
    const Color e_ms = kInvPi * albedo * albedo * (e_avg / (1.0 - e_avg)) / (Color(1.0) - albedo * (1.0 - e_avg));
    f += e_ms * (1.0 - (a * kPi + b * oren_nayar_g(nv))) * (1.0 - (a * kPi + b * oren_nayar_g(nl)));
  }
  return f;
}

}  // namespace

Color oren_nayar_eval(const OrenNayarParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (glm::dot(wo, sp.ng) * glm::dot(wi, sp.ng) <= 0.0) return Color(0.0);
  const Vec3 n = facing_normal(sp, wo);
  const double nl = glm::dot(n, wi), nv = std::fmax(glm::dot(n, wo), 0.0);
  if (nl <= 0.0) return Color(0.0);  // below the shading normal's horizon, as Cycles
  return p.color * oren_nayar_shape(p, nl, nv, glm::dot(wi, wo));
}

bool oren_nayar_sample(const OrenNayarParams& p, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                       BsdfSample& out) {
  if (!lambert_sample(p.color, sp, wo, u1, u2, false, out)) return false;
  out.weight = kPi * oren_nayar_eval(p, sp, wo, out.wi);  // f cos / (cos / pi)
  return true;
}

Color velvet_eval(const Color& color, double sigma, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (glm::dot(wo, sp.ng) * glm::dot(wi, sp.ng) <= 0.0) return Color(0.0);
  const Vec3 n = facing_normal(sp, wo);
  const double cos_o = glm::dot(n, wo), cos_i = glm::dot(n, wi);
  if (!(cos_o > 0.0 && cos_i > 0.0)) return Color(0.0);
  const Vec3 h = glm::normalize(wo + wi);
  const double cos_h = glm::dot(n, h), cos_ho = std::fabs(glm::dot(wo, h));
  if (!(std::fabs(cos_h) < 1.0 - 1e-5 && cos_ho > 1e-5)) return Color(0.0);
  const double inv_sigma2 = 1.0 / (std::fmax(sigma, 0.01) * std::fmax(sigma, 0.01));
  const double ratio = std::fmax(cos_h / cos_ho, 1e-5);
  const double sin2 = 1.0 - cos_h * cos_h, cot2 = cos_h * cos_h / sin2;
  const double d = std::exp(-cot2 * inv_sigma2) * inv_sigma2 * kInvPi / (sin2 * sin2);
  const double g = std::fmin(1.0, std::fmin(2.0 * std::fabs(ratio * cos_o), 2.0 * std::fabs(ratio * cos_i)));
  return color * (0.25 * d * g / (cos_o * cos_i));
}

bool velvet_sample(const Color& color, double sigma, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                   BsdfSample& out) {
  const Vec3 n = facing_normal(sp, wo);
  out.wi = to_world(sample_uniform_hemisphere(u1, u2), n);
  out.weight = velvet_eval(color, sigma, sp, wo, out.wi) * (glm::dot(out.wi, n) * 2.0 * kPi);
  out.specular = false;
  out.ray_kind = kDiffuseRay;
  return max_component(out.weight) > 0.0;
}

Color schlick_sheen_eval(const Color& color, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (glm::dot(wo, sp.ng) * glm::dot(wi, sp.ng) <= 0.0) return Color(0.0);
  const Vec3 n = facing_normal(sp, wo);
  if (glm::dot(n, wi) < 0.0 || glm::dot(n, wo) < 0.0) return Color(0.0);
  const double m = glm::clamp(1.0 - glm::dot(wi, glm::normalize(wo + wi)), 0.0, 1.0);
  return color * (m * m * m * m * m);
}

bool schlick_sheen_sample(const Color& color, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                          BsdfSample& out) {
  if (!lambert_sample(color, sp, wo, u1, u2, false, out)) return false;
  out.weight = kPi * schlick_sheen_eval(color, sp, wo, out.wi);  // f cos / (cos / pi)
  return max_component(out.weight) > 0.0;
}

// A conductor's distribution: its alphas along and across its tangent.
Microfacet conductor_microfacet(const ConductorParams& p) {
  const double a = alpha_of(p.roughness);
  const bool anisotropic = p.tangent != Vec3(0.0);
  const double sx = anisotropic ? p.stretch_x : 1.0, sy = anisotropic ? p.stretch_y : 1.0;
  return {std::fmax(a * sx, 1e-4), std::fmax(a * sy, 1e-4), p.beckmann};
}

Color conductor_eval(const ConductorParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (p.roughness < kSmoothRoughness) return Color(0.0);
  const LocalFrame f(facing_normal(sp, wo), p.tangent);
  const Vec3 lo = f.to_local(wo), li = f.to_local(wi);
  if (lo.z <= 0.0 || li.z <= 0.0) return Color(0.0);
  const Microfacet m = conductor_microfacet(p);
  const Vec3 h = glm::normalize(lo + li);
  return reflectance(p, glm::dot(lo, h)) * m.d(h) * m.g2(lo, li) / (4.0 * lo.z * li.z);
}

bool conductor_sample(const ConductorParams& p, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                      BsdfSample& out) {
  const Vec3 n = facing_normal(sp, wo);
  out.ray_kind = kGlossyRay;
  if (p.roughness < kSmoothRoughness) {
    const double mu = glm::dot(wo, n);
    if (mu <= 0.0) return false;
    out.wi = reflect(wo, n);
    out.weight = reflectance(p, mu);
    out.specular = true;
    return true;
  }
  const LocalFrame f(n, p.tangent);
  const Vec3 lo = f.to_local(wo);
  if (lo.z <= 0.0) return false;
  const Microfacet m = conductor_microfacet(p);
  const Vec3 h = m.sample(lo, u1, u2);
  const double oh = glm::dot(lo, h);
  if (oh <= 0.0) return false;
  const Vec3 li = reflect(lo, h);
  if (li.z <= 0.0) return false;
  out.wi = f.to_world(li);
  out.weight = reflectance(p, oh) * m.sample_weight(lo, li, h);
  out.specular = false;
  return true;
}

double conductor_pdf(const ConductorParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (p.roughness < kSmoothRoughness) return 0.0;
  const LocalFrame f(facing_normal(sp, wo), p.tangent);
  const Vec3 lo = f.to_local(wo), li = f.to_local(wi);
  if (lo.z <= 0.0 || li.z <= 0.0) return 0.0;
  const Vec3 h = glm::normalize(lo + li);
  const double oh = glm::dot(lo, h);
  return oh > 0.0 ? conductor_microfacet(p).pdf(lo, h) / (4.0 * oh) : 0.0;
}

FresnelSplit fresnel_split(const DielectricParams& p, double F) {
  // Refraction alone (Cycles' Refraction BSDF) has no Fresnel: all of it passes, but for total
  // internal reflection, where the path ends.
  if (p.parts == kRefraction) return {Color(0.0), F < 1.0 ? p.refraction_tint : Color(0.0)};
  if (!p.tint_f0) return {p.reflection_tint * F, p.refraction_tint * (1.0 - F)};
  const double f0 = (p.ior - 1.0) * (p.ior - 1.0) / ((p.ior + 1.0) * (p.ior + 1.0));
  const double s = f0 < 1.0 ? glm::clamp((F - f0) / (1.0 - f0), 0.0, 1.0) : 1.0;
  const Color reflected = glm::mix(p.reflection_tint * f0, Color(1.0), s);
  return {reflected, p.refraction_tint * (Color(1.0) - reflected)};
}

Color dielectric_eval(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (p.roughness < kSmoothRoughness) return Color(0.0);
  const DielectricSide s = dielectric_side(p, sp, wo);
  const LocalFrame f(s.n);
  const Vec3 lo = f.to_local(wo), li = f.to_local(wi);
  if (lo.z <= 0.0 || li.z == 0.0) return Color(0.0);
  const Microfacet m = dielectric_microfacet(p);
  if (li.z > 0.0) {
    if (!(p.parts & kReflection)) return Color(0.0);
    const Vec3 h = glm::normalize(lo + li);
    const double F = fresnel_dielectric(glm::dot(lo, h), s.eta_o, s.eta_i);
    return fresnel_split(p, F).reflected * (m.d(h) * m.g2(lo, li) / (4.0 * lo.z * li.z));
  }
  if (!(p.parts & kRefraction)) return Color(0.0);
  // Walter 2007, eq. 21, with wi the light side, times (eta_i / eta_o)^2: Cycles' rule, radiance
  // passing the interface unscaled (see dielectric_sample), which photons follow too.
  Vec3 h;
  double oh, ih;
  if (!refraction_half_vector(s, lo, li, h, oh, ih)) return Color(0.0);
  const double F = fresnel_dielectric(oh, s.eta_o, s.eta_i);
  const double denom = s.eta_i * ih + s.eta_o * oh;
  const Vec3 li_up(li.x, li.y, -li.z);
  const double value = std::fabs(ih) * oh * s.eta_i * s.eta_i * m.d(h) * m.g2(lo, li_up) /
                       (lo.z * std::fabs(li.z) * denom * denom);
  return fresnel_split(p, F).refracted * value;
}

double dielectric_pdf(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (p.roughness < kSmoothRoughness) return 0.0;
  const DielectricSide s = dielectric_side(p, sp, wo);
  const LocalFrame f(s.n);
  const Vec3 lo = f.to_local(wo), li = f.to_local(wi);
  if (lo.z <= 0.0 || li.z == 0.0) return 0.0;
  const Microfacet m = dielectric_microfacet(p);
  const bool both = p.parts == kReflectionAndRefraction;
  if (li.z > 0.0) {  // reflected: chosen with probability F where both parts are
    if (!(p.parts & kReflection)) return 0.0;
    const Vec3 h = glm::normalize(lo + li);
    const double oh = glm::dot(lo, h);
    if (oh <= 0.0) return 0.0;
    Vec3 t;
    const double F = refract(lo, h, s.eta_o / s.eta_i, t) ? fresnel_dielectric(oh, s.eta_o, s.eta_i) : 1.0;
    return (both ? F : 1.0) * m.pdf(lo, h) / (4.0 * oh);
  }
  if (!(p.parts & kRefraction)) return 0.0;
  Vec3 h;
  double oh, ih;
  if (!refraction_half_vector(s, lo, li, h, oh, ih)) return 0.0;
  const double F = fresnel_dielectric(oh, s.eta_o, s.eta_i);
  const double denom = s.eta_i * ih + s.eta_o * oh;  // the half vector's change with wi (Walter 2007)
  return (both ? 1.0 - F : 1.0) * m.pdf(lo, h) * s.eta_i * s.eta_i * std::fabs(ih) / (denom * denom);
}

int dielectric_branches(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, bool photon,
                        BsdfSample out[2]) {
  const DielectricSide s = dielectric_side(p, sp, wo);
  const double mu = glm::dot(wo, s.n);
  if (mu <= 0.0) return 0;
  const double F = fresnel_dielectric(mu, s.eta_o, s.eta_i);
  Vec3 t(0.0);
  const bool refracts = F < 1.0 && refract(wo, s.n, s.eta_o / s.eta_i, t);
  const FresnelSplit split = fresnel_split(p, refracts ? F : 1.0);
  int count = 0;
  if (p.parts & kReflection) out[count++] = BsdfSample{reflect(wo, s.n), split.reflected, true, kGlossyRay};
  if ((p.parts & kRefraction) && refracts) {
    const double scale = photon ? (s.eta_o / s.eta_i) * (s.eta_o / s.eta_i) : 1.0;
    out[count++] = BsdfSample{t, split.refracted * scale, true, kTransmissionRay};
  }
  return count;
}

bool dielectric_sample(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                       double u3, bool photon, BsdfSample& out) {
  if (p.roughness < kSmoothRoughness) {
    BsdfSample branches[2];
    const int count = dielectric_branches(p, sp, wo, photon, branches);
    if (count == 0) return false;
    if (count == 1) {
      out = branches[0];
      return true;
    }
    // Choose by the branches' weights, then divide by the choice probability.
    const double w0 = luminance(branches[0].weight), w1 = luminance(branches[1].weight);
    const double p0 = w0 + w1 > 0.0 ? w0 / (w0 + w1) : 0.5;
    out = u3 < p0 ? branches[0] : branches[1];
    out.weight /= u3 < p0 ? p0 : 1.0 - p0;
    return true;
  }
  const DielectricSide s = dielectric_side(p, sp, wo);
  const LocalFrame f(s.n);
  const Vec3 lo = f.to_local(wo);
  if (lo.z <= 0.0) return false;
  const Microfacet m = dielectric_microfacet(p);
  const Vec3 h = m.sample(lo, u1, u2);
  const double oh = glm::dot(lo, h);
  if (oh <= 0.0) return false;
  const double F = fresnel_dielectric(oh, s.eta_o, s.eta_i);
  Vec3 li(0.0);
  const bool refracts = refract(lo, h, s.eta_o / s.eta_i, li);
  // Both parts: reflect with probability F, dividing by it; one part: its share, not chosen.
  const bool both = p.parts == kReflectionAndRefraction;
  const double F_eff = refracts ? F : 1.0;
  const FresnelSplit split = fresnel_split(p, F_eff);
  const bool reflects = both ? u3 < F_eff : p.parts == kReflection;
  out.specular = false;
  if (reflects) {
    li = reflect(lo, h);
    if (li.z <= 0.0) return false;
    out.weight = split.reflected * ((both ? 1.0 / F_eff : 1.0) * m.sample_weight(lo, li, h));
    out.ray_kind = kGlossyRay;
  } else {
    if (!refracts || li.z >= 0.0) return false;
    const double scale = photon ? (s.eta_o / s.eta_i) * (s.eta_o / s.eta_i) : 1.0;  // Cycles' rule (lobes.h)
    const double g = m.sample_weight(lo, Vec3(li.x, li.y, -li.z), h);
    out.weight = split.refracted * ((both ? 1.0 / (1.0 - F_eff) : 1.0) * scale * g);
    out.ray_kind = kTransmissionRay;
  }
  out.wi = f.to_world(li);
  return true;
}

}  // namespace ppm
