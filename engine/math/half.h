// IEEE half floats for finite values, branch-light so that converting a 16k
// texture's billion values, and decoding texels on every lookup, stay cheap
// (glm::packHalf1x16 handles Inf and NaN too, and costs 5x more).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace ppm {

constexpr float kMaxHalf = 65504.0f;

inline uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

inline float bits_float(uint32_t u) {
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

// Rounds to the nearest half (ties to even). `f` must not be NaN; it is clamped
// to [-65504, 65504], so infinities become the largest half.
inline uint16_t to_half(float f) {
  uint32_t x = float_bits(std::clamp(f, -kMaxHalf, kMaxHalf));
  const uint32_t sign = (x >> 16) & 0x8000u;
  x &= 0x7fffffffu;
  uint32_t h;
  if (x < 0x38800000u) {
    // Below 2^-14, the smallest normal half: the FPU rounds |f| into the
    // multiples of 2^-24 (half's subnormal step) that 0.5 + |f| can hold.
    h = float_bits(bits_float(x) + 0.5f) - 0x3f000000u;
  } else {
    // Rebias the exponent (127 -> 15) and round the 13 dropped mantissa bits
    // to nearest, ties to even; a carry moves into the exponent as it should.
    x += (static_cast<uint32_t>(15 - 127) << 23) + 0xfffu + ((x >> 13) & 1u);
    h = x >> 13;
  }
  return static_cast<uint16_t>(h | sign);
}

// Exact for every finite half, subnormals included: the half's exponent and
// mantissa bits placed in a float and scaled by 2^(127 - 15).
inline float from_half(uint16_t h) {
  const uint32_t sign = static_cast<uint32_t>(h & 0x8000u) << 16;
  const float magnitude = bits_float(static_cast<uint32_t>(h & 0x7fffu) << 13) * bits_float(0x77800000u);
  return bits_float(float_bits(magnitude) | sign);
}

}  // namespace ppm
