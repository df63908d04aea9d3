// A mixture of weighted lobes: evaluation, sampling and the split the eye pass needs between the
// delta lobes it follows and the rest, which a hit point stores. Layering follows Cycles'
// Principled BSDF: a `layer` lobe attenuates every lobe after it by 1 - max(its directional albedo
// towards the viewer). Sampling picks one lobe (probabilities from the lobes' weights and albedos),
// samples it and divides by the pick's probability: unbiased, and no lobe needs a pdf.
#pragma once

#include "shading/lobe.h"

#include <vector>

namespace ppm {

// Tabulates a layer's directional albedo (lobe.h); other lobes are left as they are.
void prepare_lobe(Lobe& lobe);

// f(wo, wi) of the non-delta lobes, without the cosine.
Color closure_eval(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);

// Samples the next direction. `adjoint`: a photon, which arrived along -wo; its layers attenuate
// by the albedo towards where it leaves (the viewer's side of its reversed path), so that photons
// carry what the eye side evaluates, and refraction follows Cycles' rule (dielectric_sample).
bool closure_sample(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, double u_pick,
                    double u1, double u2, double u3, bool adjoint, BsdfSample& out);

// The share of the delta lobes in what the surface sends towards wo (0: none, 1: delta only).
double closure_delta_share(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo);

// For eye paths: the branches of one delta lobe, picked among them with u; weights divided by the
// pick's probability within the delta lobes (the caller divides by closure_delta_share).
int closure_delta_branches(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, double u,
                           BsdfSample out[2]);

bool closure_has_delta(const std::vector<Lobe>& lobes);
bool closure_is_delta(const std::vector<Lobe>& lobes);
bool closure_transmits(const std::vector<Lobe>& lobes);  // a non-delta lobe scatters to the far side

}  // namespace ppm
