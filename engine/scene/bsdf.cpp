// BSDF evaluation and sampling per material kind (see bsdf.h).
#include "scene/bsdf.h"

#include "shading/lobes.h"
#include "shading/microfacet.h"

namespace ppm {
namespace {

// A mirror reflects its colour at every angle, perfectly smooth whatever its roughness says.
ConductorParams conductor(const Material& m, const SurfacePoint& sp) {
  const bool mirror = m.kind == MaterialKind::Mirror;
  return {sp.albedo, m.specular_tint, mirror ? 0.0 : m.roughness, mirror};
}
DielectricParams dielectric(const Material& m) { return {m.ior, m.roughness, Color(1.0), m.base_color}; }

}  // namespace

Color bsdf_eval(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  switch (m.kind) {
    case MaterialKind::Diffuse: return lambert_eval(sp.albedo, sp, wo, wi, false);
    case MaterialKind::Metal: return conductor_eval(conductor(m, sp), sp, wo, wi);
    case MaterialKind::Glass: return dielectric_eval(dielectric(m), sp, wo, wi);
    case MaterialKind::Mixture: return closure_eval(m.lobes, sp, wo, wi);
    case MaterialKind::Mirror:
    case MaterialKind::Emission:
    case MaterialKind::Holdout: return Color(0.0);
  }
  return Color(0.0);
}

bool bsdf_lambertian(const Material& m, const SurfacePoint& sp, const Vec3& wo, Color& albedo) {
  albedo = sp.albedo;
  if (m.kind == MaterialKind::Diffuse) return true;
  return m.kind == MaterialKind::Mixture && closure_lambertian(m.lobes, sp, wo, albedo);
}

ClassColors bsdf_eval_classes(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  if (m.kind == MaterialKind::Mixture) return closure_eval_classes(m.lobes, sp, wo, wi);
  ClassColors f;
  const bool reflected = glm::dot(wo, sp.ng) * glm::dot(wi, sp.ng) > 0.0;
  const int c = m.kind == MaterialKind::Diffuse ? kDiffuseClass : reflected ? kGlossyClass : kTransmissionClass;
  f.c[c] = bsdf_eval(m, sp, wo, wi);
  return f;
}

ClassColors bsdf_class_albedo(const Material& m, const SurfacePoint& sp, const Vec3& wo) {
  ClassColors albedo;
  switch (m.kind) {
    case MaterialKind::Diffuse: albedo.c[kDiffuseClass] = sp.albedo; break;
    case MaterialKind::Mirror:
    case MaterialKind::Metal: albedo.c[kGlossyClass] = sp.albedo; break;
    case MaterialKind::Glass: {
      const double mu = glm::clamp(std::fabs(glm::dot(wo, sp.ns)), 0.0, 1.0);
      const double F = glm::dot(wo, sp.ng) < 0.0 ? fresnel_dielectric(mu, m.ior, 1.0) : fresnel_dielectric(mu, 1.0, m.ior);
      albedo.c[kGlossyClass] = Color(F);
      albedo.c[kTransmissionClass] = m.base_color * (1.0 - F);
      break;
    }
    case MaterialKind::Mixture: return closure_class_albedo(m.lobes, sp, wo);
    case MaterialKind::Emission:
    case MaterialKind::Holdout: break;
  }
  return albedo;
}

bool bsdf_sample(const Material& m, const SurfacePoint& sp, const Vec3& wo, double u1, double u2, double u3,
                 double u4, bool adjoint, BsdfSample& out) {
  switch (m.kind) {
    case MaterialKind::Diffuse: return lambert_sample(sp.albedo, sp, wo, u1, u2, false, out);
    case MaterialKind::Mirror:
    case MaterialKind::Metal: return conductor_sample(conductor(m, sp), sp, wo, u1, u2, out);
    case MaterialKind::Glass: return dielectric_sample(dielectric(m), sp, wo, u1, u2, u3, adjoint, out);
    case MaterialKind::Mixture: return closure_sample(m.lobes, sp, wo, u4, u1, u2, u3, adjoint, out);
    case MaterialKind::Emission:
    case MaterialKind::Holdout: return false;
  }
  return false;
}

int specular_branches(const Material& m, const SurfacePoint& sp, const Vec3& wo, double u, double u1, double u2,
                      double u3, BsdfSample out[2]) {
  switch (m.kind) {
    case MaterialKind::Mirror:
    case MaterialKind::Metal: return conductor_sample(conductor(m, sp), sp, wo, 0.5, 0.5, out[0]) ? 1 : 0;
    case MaterialKind::Glass: return dielectric_branches(dielectric(m), sp, wo, false, out);
    case MaterialKind::Mixture: return closure_followed_branches(m.lobes, sp, wo, u, u1, u2, u3, out);
    default: return 0;
  }
}

}  // namespace ppm
