// The scattering functions of the lobe families, on plain parameters, so that the single-kind
// materials (scene/bsdf.h) and mixtures (shading/closure.h) share one implementation of each.
// Rough lobes use GGX or Beckmann (microfacet.h); rough refraction follows Walter et al. 2007.
#pragma once

#include "shading/scatter.h"

namespace ppm {

// f of a Lambertian surface on wo's side (reflection) or the far side (translucency).
Color lambert_eval(const Color& color, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi, bool far_side);
bool lambert_sample(const Color& color, const SurfacePoint& sp, const Vec3& wo, double u1, double u2, bool far_side,
                    BsdfSample& out);

// Rough diffuse reflection as Cycles' Diffuse BSDF with Roughness > 0: Fujii's improved
// Oren-Nayar model, f = color (a + b t), a = 1 / (pi + sigma (pi/2 - 2/3)), b = sigma a, t the
// angle term (l.v - (n.l)(n.v)) / max(n.l, n.v) where positive; with `multiscatter`, Blender 4.3
// and later's energy compensation (OpenPBR's, after Portsmouth et al.), which gives back what single
// scattering loses. Sampled cosine-weighted, as Cycles.
struct OrenNayarParams {
  Color color;
  double sigma;  // Blender's roughness in [0, 1]
  bool multiscatter;
};
Color oren_nayar_eval(const OrenNayarParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);
bool oren_nayar_sample(const OrenNayarParams& p, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                       BsdfSample& out);

// Sheen. Velvet: Ashikhmin's microfacet velvet as Cycles has it (the Velvet BSDF of 3.x, the Sheen
// BSDF's Ashikhmin mode), D = exp(-cot^2(theta_h) / sigma^2) / (pi sigma^2 sin^4(theta_h)),
// G = min(1, 2 cos_h cos_o / |o.h|, 2 cos_h cos_i / |o.h|), sampled uniformly over the hemisphere.
// Schlick sheen: the Principled BSDF's of 3.x, color (1 - l.h)^5, sampled cosine-weighted.
Color velvet_eval(const Color& color, double sigma, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);
bool velvet_sample(const Color& color, double sigma, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                   BsdfSample& out);
Color schlick_sheen_eval(const Color& color, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);
bool schlick_sheen_sample(const Color& color, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                          BsdfSample& out);

struct ConductorParams {
  Color f0;   // reflectance at normal incidence (Blender's base colour)
  Color f82;  // the F82 tint
  double roughness;
  bool constant = false;  // reflectance f0 at every angle (Cycles' Glossy BSDF), no Fresnel
  // Anisotropy: GGX alpha = roughness^2 times stretch_x along `tangent` (projected on the surface)
  // and stretch_y across it; a zero tangent leaves the lobe isotropic.
  Vec3 tangent{0.0};
  double stretch_x = 1.0, stretch_y = 1.0;
  bool beckmann = false;  // Beckmann's distribution rather than GGX
};
Color conductor_eval(const ConductorParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);
bool conductor_sample(const ConductorParams& p, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                      BsdfSample& out);
// The density (per solid angle) of conductor_sample's directions at wi (0 for a smooth conductor).
double conductor_pdf(const ConductorParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);

enum DielectricParts : uint8_t { kReflection = 1, kRefraction = 2, kReflectionAndRefraction = 3 };
struct DielectricParams {
  double ior;
  double roughness;
  Color reflection_tint;
  Color refraction_tint;
  uint8_t parts = kReflectionAndRefraction;
  bool tint_f0 = false;  // the reflection tint scales F0 only, as Cycles' generalized Schlick Fresnel
                         // of the Principled BSDF; else it scales the whole reflection
  bool beckmann = false;  // Beckmann's distribution rather than GGX
};

// The reflected and refracted shares of light at a (micro)surface of real Fresnel reflectance F.
struct FresnelSplit {
  Color reflected, refracted;
};
FresnelSplit fresnel_split(const DielectricParams& p, double F);
Color dielectric_eval(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);
// `photon`: Cycles lets radiance pass an interface unscaled, so a surface behind a single glass
// surface (a pane, a water surface) gets 1/eta^2 of the flux that crosses; photons follow that rule
// (refraction scales them by (eta_o / eta_i)^2, eta_o on the side they come from), so that such a
// surface is as bright as in Cycles. Into and out of a closed object the factors cancel.
bool dielectric_sample(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                       double u3, bool photon, BsdfSample& out);
// The density (per solid angle) of dielectric_sample's directions at wi, the choice between
// reflection and refraction included (0 for a smooth dielectric).
double dielectric_pdf(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);
// Both branches of a smooth dielectric with their Fresnel weights (0 to 2 written). `photon`: the
// refraction also scales by (eta_o / eta_i)^2 (see dielectric_sample).
int dielectric_branches(const DielectricParams& p, const SurfacePoint& sp, const Vec3& wo, bool photon,
                        BsdfSample out[2]);
}  // namespace ppm
