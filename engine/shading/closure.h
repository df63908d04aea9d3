// A mixture of weighted lobes: evaluation, sampling and the split the eye pass needs between the
// lobes it follows (microfacet and transparent ones, Lobe::followed) and the rest, which a hit
// point stores. Layering follows Cycles' Principled BSDF: a `layer` lobe attenuates every lobe after it
// by 1 - max(its directional albedo towards the viewer), so that a layer over a white base loses
// nothing (as Cycles 5 measures), and a `multiscatter` lobe gets back the energy GGX single
// scattering loses, as Cycles' Multiscatter GGX. Sampling picks one lobe (probabilities from the
// lobes' weights and albedos), samples it and divides by the pick's probability: unbiased, and no
// lobe needs a pdf.
#pragma once

#include "shading/light_class.h"
#include "shading/lobe.h"

#include <vector>

namespace ppm {

// Tabulates a layer's directional albedo (lobe.h); other lobes are left as they are.
void prepare_lobe(Lobe& lobe);

// f(wo, wi) of the lobes hit points store (all but the followed ones), without the cosine.
Color closure_eval(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);

// f(wo, wi) of the followed lobes that are not delta at sp (rough glossy, metal, glass and coats),
// without the cosine: what an eye path that follows them reflects of a sampled light
// (EyeTracer::sample_lights).
Color closure_eval_followed_rough(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo,
                                  const Vec3& wi);
bool closure_has_rough_followed(const std::vector<Lobe>& lobes, const SurfacePoint& sp);
// The density (per solid angle) at wi of the directions closure_followed_branches draws from its
// lobes that are not delta (a delta lobe's direction has no density: those are left out).
double closure_followed_pdf(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);

// Whether closure_eval at sp, seen from wo, is Lambertian reflection of `albedo` for every wi on wo's
// side: each lobe it evaluates (those not followed) a smooth Diffuse one, and no bump shadowing (a
// diffuse and a mirror mixed, a clear coat over paint). A hit point there gathers as a diffuse one.
bool closure_lambertian(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, Color& albedo);

// closure_eval split by the class of the lobes (light_class.h).
ClassColors closure_eval_classes(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo,
                                 const Vec3& wi);

// Samples the next direction. `adjoint`: a photon, which arrived along -wo; its layers attenuate
// by the albedo towards where it leaves (the viewer's side of its reversed path), so that photons
// carry what the eye side evaluates, and refraction follows Cycles' rule (dielectric_sample).
bool closure_sample(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, double u_pick,
                    double u1, double u2, double u3, bool adjoint, BsdfSample& out);

// The share of the followed lobes in what the surface sends towards wo (0: none, 1: only them).
double closure_followed_share(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo);

// For eye paths: the branches of one followed lobe, picked among them with u (a rough one sampled
// with u1 to u3); weights divided by the pick's probability within the followed lobes (the caller
// divides by closure_followed_share).
int closure_followed_branches(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, double u,
                              double u1, double u2, double u3, BsdfSample out[2]);

// Cycles' Denoising Albedo of the lobes hit points store: each lobe's colour (a layer's and a
// dielectric's: their reflectance towards wo, tinted) times its weight after the layers above.
Color closure_albedo(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo);

// Cycles' Denoising Albedo of the followed lobes it counts as rough (Lobe::rough_for_denoising):
// each one's reflectance towards wo (a dielectric's reflection by its Fresnel reflectance, its
// refraction by the rest), tinted, times its weight after the layers above.
Color closure_followed_albedo(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo);

// Cycles' Diffuse, Glossy and Transmission Color of all the lobes, the followed ones too: each
// lobe's colour times its weight, a dielectric's reflection by its Fresnel reflectance towards wo
// and its refraction by the rest.
ClassColors closure_class_albedo(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo);

bool closure_has_followed(const std::vector<Lobe>& lobes);
bool closure_is_followed(const std::vector<Lobe>& lobes);
bool closure_transmits(const std::vector<Lobe>& lobes);  // a stored lobe scatters to the far side

}  // namespace ppm
