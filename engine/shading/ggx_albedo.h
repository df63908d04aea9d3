// The directional albedo E(roughness, cos_theta) of a GGX reflection lobe with Fresnel 1, and its
// cosine-weighted average E_avg(roughness): what single scattering keeps, for restoring the energy
// of multiple scattering as Cycles' Multiscatter GGX does. Tabulated once (32 x 32, as Cycles),
// by numerical integration; Blender's roughness (alpha = roughness^2) and cos_theta in [0, 1].
#pragma once

namespace ppm {

double ggx_albedo(double roughness, double cos_theta);
double ggx_average_albedo(double roughness);

}  // namespace ppm
