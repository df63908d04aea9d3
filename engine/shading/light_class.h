// The classes Cycles files light by (its Diffuse, Glossy and Transmission passes): diffuse,
// translucent and sheen lobes are diffuse; reflection by a microfacet lobe (conductor, glossy, a
// dielectric's reflection) is glossy; refraction is transmission.
#pragma once

#include "math/types.h"

#include <cstdint>

namespace ppm {

enum LightClass : uint8_t { kDiffuseClass, kGlossyClass, kTransmissionClass };
constexpr int kLightClasses = 3;

// Light split by the class of lobe that scattered it.
struct ClassColors {
  Color c[kLightClasses] = {Color(0.0), Color(0.0), Color(0.0)};
  Color total() const { return c[0] + c[1] + c[2]; }
};

}  // namespace ppm
