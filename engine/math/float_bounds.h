// Doubles rounded to float in a chosen direction, so a box stored in float
// (half the bytes of a double box) always contains the double box it came
// from: a slab test on it can report extra candidates but never lose a hit.
#pragma once

#include <cfloat>
#include <cstdint>
#include <cstring>
#include <limits>

namespace ppm {

// The next float above f (f finite); by stepping the bit pattern, which is
// several times cheaper than std::nextafter and runs once per ray.
inline float float_next_up(float f) {
  if (f == 0.0f) return std::numeric_limits<float>::denorm_min();
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  bits += f > 0.0f ? 1 : -1;  // magnitude up for positive, down for negative
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// Smallest float >= x (+inf above float range).
inline float float_up(double x) {
  if (x > FLT_MAX) return std::numeric_limits<float>::infinity();
  if (x < -FLT_MAX) return -FLT_MAX;  // out-of-range conversions are explicit, not left to the cast
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? float_next_up(f) : f;
}

// Largest float <= x (-inf below float range).
inline float float_down(double x) { return -float_up(-x); }

// A float >= x (x not NaN), at most two ulps above it, +inf above FLT_MAX.
// Without the comparisons of float_up, whose outcome is a coin toss per ray:
// it steps up one ulp from the nearest float whether or not that was needed.
inline float float_above(double x) {
  x = x < FLT_MAX ? x : FLT_MAX;  // no out-of-range conversion (FLT_MAX steps up to +inf)
  x = x > -FLT_MAX ? x : -FLT_MAX;
  const float f = static_cast<float>(x) + 0.0f;  // + 0 turns -0 into +0
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  bits += 1u - ((bits >> 31) << 1);  // +1 (magnitude up) if positive, -1 (magnitude down) if negative
  float up;
  std::memcpy(&up, &bits, sizeof up);
  return up;
}

// A float <= x (x not NaN), at most two ulps below it, -inf below -FLT_MAX.
inline float float_below(double x) { return -float_above(-x); }

}  // namespace ppm
