// Scattering at a surface: evaluation and sampling of every material kind, dispatched by a switch
// on the kind (no virtual calls in the hot loops); each kind's math is in shading/lobes.h, a
// mixture's in shading/closure.h. Directions point away from the surface: `wo` towards the viewer
// or the previous path vertex, `wi` towards the light or the next vertex.
#pragma once

#include "scene/material.h"
#include "shading/scatter.h"

namespace ppm {

// f(wo, wi), without the cosine. Zero for delta lobes.
Color bsdf_eval(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);

// Whether bsdf_eval at sp, seen from wo, is Lambertian reflection of `albedo` for every wi on wo's
// side (a Diffuse material, or a mixture whose evaluated lobes are: closure_lambertian): hit points
// there weigh every photon alike.
bool bsdf_lambertian(const Material& m, const SurfacePoint& sp, const Vec3& wo, Color& albedo);

// bsdf_eval split by the class of lobe that scatters (shading/light_class.h).
ClassColors bsdf_eval_classes(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);

// Cycles' Diffuse, Glossy and Transmission Color passes at a surface seen from wo: each class's
// albedo, delta lobes included.
ClassColors bsdf_class_albedo(const Material& m, const SurfacePoint& sp, const Vec3& wo);

// Samples wi given wo; u4 picks a mixture's lobe. `adjoint`: a photon (see closure_sample and
// dielectric_sample).
// Returns false when the path should end (absorbed, or a sample below the surface).
bool bsdf_sample(const Material& m, const SurfacePoint& sp, const Vec3& wo, double u1, double u2, double u3,
                 double u4, bool adjoint, BsdfSample& out);

// The branches of a smooth surface, so the eye pass can follow reflection and refraction with their
// Fresnel weights instead of choosing one at random; for a mixture, those of one followed lobe
// picked with u, a rough one sampled with u1 to u3 (see closure_followed_branches). Returns the
// number of branches written (0 to 2).
int specular_branches(const Material& m, const SurfacePoint& sp, const Vec3& wo, double u, double u1, double u2,
                      double u3, BsdfSample out[2]);

// The RayKind a material's non-delta scattering gives rays (for bounce counts at hit points).
inline uint8_t scattering_ray_kind(const Material& m) {
  if (m.kind == MaterialKind::Diffuse) return kDiffuseRay;
  if (m.kind == MaterialKind::Mixture)
    for (const Lobe& l : m.lobes)
      if (l.diffuse() || l.sheen()) return kDiffuseRay;
  return kGlossyRay;
}

}  // namespace ppm
