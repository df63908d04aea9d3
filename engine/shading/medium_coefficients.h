// A medium's coefficients at a point (RGB, per metre): absorption, scattering, emission and the
// phase function of the scattering part, and the volume shader nodes' inputs turned into them as
// Cycles' SVM does (intern/cycles/kernel/svm/closure.h: svm_node_closure_volume,
// svm_node_volume_coefficients, svm_node_principled_volume; svm_node_closure_emission).
//
// `weight` below is Cycles' mix weight times object_volume_density (1 unless the object says
// otherwise). Where Cycles would produce a negative or NaN coefficient (a Color above 1 in Volume
// Absorption, a negative Volume Coefficients input, NaN anywhere) the coefficient here is 0: the
// free-path samplers need sigma >= 0, and Cycles' answer there is not a defined image.
#pragma once

#include "math/types.h"
#include "shading/phase.h"

namespace ppm {

struct MediumCoefficients {
  Color sigma_a{0.0};   // absorption
  Color sigma_s{0.0};   // scattering
  Color emission{0.0};  // radiance added per unit length
  Phase phase;          // of the scattering
  Color sigma_t() const { return sigma_a + sigma_s; }
};

// Volume Absorption: sigma_a = (1 - color) density.
MediumCoefficients volume_absorption(const Color& color, double density, double weight = 1.0);
// Volume Scatter: sigma_s = color density; it does not absorb.
MediumCoefficients volume_scatter(const Color& color, double density, const Phase& phase, double weight = 1.0);
// Emission (or Add Shader's emission) in a volume: color strength, per unit length.
MediumCoefficients volume_emission(const Color& color, double strength, double weight = 1.0);
// Volume Coefficients (Blender 5.0): the coefficients given directly.
MediumCoefficients volume_coefficients(const Color& absorption, const Color& scatter, const Color& emission,
                                       const Phase& phase, double weight = 1.0);

// The Principled Volume node's inputs (Blender's defaults). `density` is the Density input already
// multiplied by the density attribute where the object has one (Cycles' attr_density), and
// `temperature` by the temperature attribute (attr_temperature).
struct PrincipledVolumeInputs {
  Color color{0.5};
  double density = 1.0;
  double anisotropy = 0.0;
  Color absorption_color{0.0};
  double emission_strength = 0.0;
  Color emission_color{1.0};
  double blackbody_intensity = 0.0;
  Color blackbody_tint{1.0};
  double temperature = 1000.0;
};

// Cycles' Principled Volume:
//   density' = weight max(density, 0); sigma_s = color density'
//   sigma_a = max(1 - color, 0) max(1 - sqrt(absorption_color), 0) density'
//   emission = weight (emission_strength emission_color
//              + blackbody_tint I(T) blackbody_color(T)),   I = sigma_SB 1e-6 / pi mix(1, T^4, intensity)
// with the blackbody term only where blackbody_intensity > 0, T = max(temperature, 0).
// `blackbody_color` is the Blackbody node's scene-linear colour at T: the core has no table of its
// own (export/blackbody.py hands its fit to the node program's Blackbody instruction).
// TODO(media): evaluate it in the core once the fit lives there.
MediumCoefficients principled_volume(const PrincipledVolumeInputs& in, const Color& blackbody_color,
                                     double weight = 1.0);
// The Stefan-Boltzmann factor I(T) above (W m^-2 K^-4 times 1e-6 / pi, Cycles' units).
double principled_volume_blackbody_intensity(double temperature, double blackbody_intensity);

}  // namespace ppm
