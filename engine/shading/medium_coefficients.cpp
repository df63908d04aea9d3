// Volume shader nodes to medium coefficients, as Cycles' SVM (medium_coefficients.h).
#include "shading/medium_coefficients.h"

#include <algorithm>
#include <cmath>

namespace ppm {
namespace {

double non_negative(double x) { return x > 0.0 ? x : 0.0; }  // NaN as 0
Color non_negative(const Color& c) { return Color(non_negative(c.x), non_negative(c.y), non_negative(c.z)); }
// Finite and >= 0: a product of finite inputs can still overflow.
Color coefficient(const Color& c) {
  Color r = non_negative(c);
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(r[i])) r[i] = 0.0;
  return r;
}
double weight_of(double weight) { return std::isfinite(weight) ? non_negative(weight) : 0.0; }

}  // namespace

MediumCoefficients volume_absorption(const Color& color, double density, double weight) {
  MediumCoefficients m;
  m.sigma_a = coefficient((Color(1.0) - color) * (weight_of(weight) * non_negative(density)));
  return m;
}

MediumCoefficients volume_scatter(const Color& color, double density, const Phase& phase, double weight) {
  MediumCoefficients m;
  m.sigma_s = coefficient(color * (weight_of(weight) * non_negative(density)));
  m.phase = phase;
  return m;
}

MediumCoefficients volume_emission(const Color& color, double strength, double weight) {
  MediumCoefficients m;
  m.emission = coefficient(color * strength * weight_of(weight));
  return m;
}

MediumCoefficients volume_coefficients(const Color& absorption, const Color& scatter, const Color& emission,
                                       const Phase& phase, double weight) {
  const double w = weight_of(weight);
  MediumCoefficients m;
  m.sigma_a = coefficient(absorption * w);
  m.sigma_s = coefficient(scatter * w);
  m.emission = coefficient(emission * w);
  m.phase = phase;
  return m;
}

double principled_volume_blackbody_intensity(double temperature, double blackbody_intensity) {
  const double t = non_negative(temperature), t4 = (t * t) * (t * t);
  constexpr double kSigma = 5.670373e-8 * 1e-6 / kPi;  // Stefan-Boltzmann, in Cycles' units
  return kSigma * ((1.0 - blackbody_intensity) + blackbody_intensity * t4);
}

MediumCoefficients principled_volume(const PrincipledVolumeInputs& in, const Color& blackbody_color, double weight) {
  const double w = weight_of(weight), density = w * non_negative(in.density);
  MediumCoefficients m;
  m.phase = henyey_greenstein_phase(in.anisotropy);
  if (density > 0.0) {
    // The square root of the absorption colour is Cycles' (svm_node_principled_volume).
    const Color absorption_color = non_negative(glm::sqrt(non_negative(in.absorption_color)));
    const Color absorption = non_negative(Color(1.0) - in.color) * non_negative(Color(1.0) - absorption_color);
    m.sigma_s = coefficient(in.color * density);
    m.sigma_a = coefficient(absorption * density);
  }
  Color emission(0.0);
  if (in.emission_strength > 0.0) emission += in.emission_strength * in.emission_color * w;
  if (in.blackbody_intensity > 0.0) {
    const double intensity = principled_volume_blackbody_intensity(in.temperature, in.blackbody_intensity);
    if (intensity > 0.0) emission += in.blackbody_tint * intensity * blackbody_color * w;
  }
  m.emission = coefficient(emission);
  return m;
}

}  // namespace ppm
