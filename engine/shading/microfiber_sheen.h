// Cycles' microfiber sheen (Blender 4.0 and later: the Sheen BSDF's default mode and the Principled
// BSDF's sheen): Zeltner, Burley and Chiang 2022's linearly transformed cosine, fitted to a layer of
// fibres standing along the normal. For a viewer wo at cos(theta) = mu, in a frame with x towards wo,
//   f(wo, wi) cos(theta_i) = color R D(M^-1 wi / |M^-1 wi|) a^2 / |M^-1 wi|^3,
//   M^-1 = [[a, 0, b], [0, a, 0], [0, 0, 1]], D(w) = max(w.z, 0) / pi,
// with (a, b, R) interpolated by mu and roughness in a 32 x 32 table that
// tools/sheen_ltc/fit_sheen_ltc.py fits to random walks through the layer. The lobe is sampled
// exactly (a cosine-distributed direction mapped by M weighs color R). It is not reciprocal, so
// photons, which scatter the other way, get the adjoint weight.
#pragma once

#include "shading/scatter.h"

namespace ppm {

// R: the share of light the fibres send back towards a viewer at cos(theta) = mu.
double microfiber_sheen_albedo(double roughness, double mu);
Color microfiber_sheen_eval(const Color& color, double roughness, const SurfacePoint& sp, const Vec3& wo,
                            const Vec3& wi);
// `photon`: wo is where the photon came from, and the weight is f(wi, wo) cos(wi) / pdf.
bool microfiber_sheen_sample(const Color& color, double roughness, const SurfacePoint& sp, const Vec3& wo,
                             double u1, double u2, bool photon, BsdfSample& out);

}  // namespace ppm
