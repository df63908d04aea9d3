// Phase functions of participating media, as Cycles defines them (intern/cycles/kernel/closure/
// volume_util.h and volume_*.h): Henyey-Greenstein, Rayleigh, Draine, Fournier-Forand, and the
// Volume Scatter node's Mie, a mixture of Henyey-Greenstein and Draine fitted to droplet diameter.
//
// Convention: every phase function here is a density over the sphere of outgoing directions (it
// integrates to 1, so pdf == value) and a function of cos_theta = dot(d_in, d_out) alone, where
// d_in is the direction the path travelled INTO the scattering point (propagation) and d_out the
// direction it leaves in. Forward scattering (g > 0) keeps d_out near d_in. This is Cycles'
// cos_theta = dot(-sd->wi, wo): its wi points back towards the viewer, so -wi is the eye path's
// propagation direction. As p depends on the cosine only, p(d_in, d_out) = p(-d_out, -d_in): eye
// paths and photon paths evaluate and sample the same function with their own travel directions.
//
// The math is written from the definitions (Henyey & Greenstein 1941; Frisvad 2011 for Rayleigh;
// Draine 2003; Fournier & Forand 1994, Fournier & Jonasz 1999; Jendersie & d'Eon 2023 for the Mie
// fit) in double. Where Cycles has a special case or a clamp, the same one is here, said so.
#pragma once

#include "math/types.h"

#include <cstdint>

namespace ppm {

// ---- The families on plain parameters: densities over the sphere, per steradian. ----

// Henyey-Greenstein: (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5); |g| < 1e-3 is exactly isotropic
// (Cycles' switch, which also makes g = 0 cost nothing).
double phase_henyey_greenstein(double cos_theta, double g);
// Rayleigh: 3 / (16 pi) (1 + cos^2).
double phase_rayleigh(double cos_theta);
// Draine: HG times (1 + alpha cos^2) / (1 + alpha (1 + 2 g^2) / 3). Cycles' special cases are kept:
// |alpha| < 1e-3 is Henyey-Greenstein; |g| < 1e-3 with alpha > 0.999 is Rayleigh (for alpha far
// from 1 too: that is what Cycles evaluates, e.g. Mie's Draine lobe of alpha 250 at tiny droplets).
double phase_draine(double cos_theta, double g, double alpha);

// Fournier-Forand's coefficients from the particles' IOR n and the backscatter fraction B (the
// share of light scattered into the back hemisphere), as Cycles' phase_fournier_forand_coeffs:
// nu from B through the closed form of B at delta_90, and the (3 cos^2 - 1) term's factor.
struct FournierForandCoefficients {
  double n = 1.33;
  double nu = 0.0;        // (3 - mu) / 2 of the Junge slope mu; negative, 0 when B is 0
  double c180 = 0.0;      // (delta_180^-nu - 1) / (delta_180 - 1)
};
FournierForandCoefficients fournier_forand_coefficients(double backscatter, double ior);
double phase_fournier_forand(double cos_theta, const FournierForandCoefficients& c);
// The same density at x = sin^2(theta / 2) = (1 - cos) / 2, which keeps precision in the forward
// peak, where cos rounds to 1.
double phase_fournier_forand_at(double x, const FournierForandCoefficients& c);

// ---- Sampling cos_theta from each family with one uniform u in [0, 1). ----
double sample_henyey_greenstein_cos(double g, double u);
double sample_rayleigh_cos(double u);
double sample_draine_cos(double g, double alpha, double u);
// Fournier-Forand samples x = sin^2(theta / 2) (see phase_fournier_forand_at).
double sample_fournier_forand_x(const FournierForandCoefficients& c, double u);

// Cycles' fit of the Mie phase function of water droplets of diameter d (micrometres, 0 to 50):
// (1 - w) HG(g_hg) + w Draine(g_draine, alpha) (phase_mie_fitted_parameters, eqs. 7-22 of the
// supplemental of Jendersie & d'Eon 2023). Cycles uses fast sin/cos/log/exp there; these are the
// exact ones, a relative difference of about 1e-6 in the parameters.
struct MieParameters {
  double g_hg = 0.0, g_draine = 0.0, alpha = 0.0, draine_weight = 0.0;
};
MieParameters mie_fitted_parameters(double diameter);

// ---- A medium's phase function: one family, or the Mie mixture of two. ----

enum class PhaseKind : uint8_t { HenyeyGreenstein, Rayleigh, Draine, FournierForand };

struct PhaseLobe {
  PhaseKind kind = PhaseKind::HenyeyGreenstein;
  double g = 0.0;      // Henyey-Greenstein, Draine: clamped to |g| <= 0.999 (Cycles' setup)
  double alpha = 0.0;  // Draine, >= 0
  FournierForandCoefficients ff;
  double eval(double cos_theta) const;
  double sample_cos(double u) const;
};

struct PhaseSample {
  Vec3 direction{0.0};  // d_out, unit length
  double pdf = 0.0;     // == eval(cos_theta): 0 only where the density is 0 (B = 0 Fournier-Forand)
  double cos_theta = 1.0;  // dot(d_in, direction) up to rounding
};

struct Phase {
  PhaseLobe first;
  PhaseLobe second;            // used when second_weight > 0 (Mie's Draine lobe)
  double second_weight = 0.0;  // the mixture (1 - w) first + w second, w in [0, 1]

  double eval(double cos_theta) const;
  double eval(const Vec3& d_in, const Vec3& d_out) const { return eval(glm::dot(d_in, d_out)); }
  // d_in: unit propagation direction into the point; u1 picks the lobe and the angle, u2 the
  // azimuth. The pdf is the mixture's, as Cycles' phase sampling evaluates all closures (MIS).
  PhaseSample sample(const Vec3& d_in, double u1, double u2) const;
};

// The Volume Scatter node's phase functions, with Cycles' clamps (each *_setup in volume_*.h):
// g to [-0.999, 0.999] (NaN as 0), alpha to >= 0 (Cycles leaves a negative alpha alone, which can
// make its density negative), B to [0, 0.499] from |B|, IOR to >= 1.001.
Phase henyey_greenstein_phase(double g);
Phase rayleigh_phase();
Phase draine_phase(double g, double alpha);
Phase fournier_forand_phase(double backscatter, double ior);
Phase mie_phase(double diameter);

// The unit direction at cos_theta from `axis`, azimuth 2 pi u (Cycles' phase_sample_direction).
Vec3 direction_around(const Vec3& axis, double cos_theta, double u);

}  // namespace ppm
