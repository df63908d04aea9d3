// A two-dimensional low-discrepancy sequence for sampling a pixel across passes: the first two
// dimensions of Sobol's sequence, a (0,2)-sequence in base 2 (any 2^m points from an index that is
// a multiple of 2^m put one point in every elementary box of area 2^-m), Owen-scrambled by a hash
// (Burley 2020, "Practical Hash-based Owen Scrambling", with the Laine-Karras style permutation
// Cycles uses in its Sobol-Burley sampler). The scrambling keeps the stratification and makes each
// point uniform on [0, 1)^2 by itself, so an average over the points is unbiased; different scramble
// seeds give independent sequences.
//
// Why: a feature much smaller than a pixel (a sun seen in a mirror ball or through a glass ball) is
// found by a fraction f of the pixel's samples. Independent samples find it Binomial(N, f) times, so
// over few passes the pixel is dark in most renders and very bright in a few; stratified ones find
// it close to f N times from the first passes on.
#pragma once

#include "math/rng.h"
#include "math/types.h"

#include <cstdint>

namespace ppm {

inline uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
}

// Owen scrambling of a 32-bit fixed-point coordinate: a random permutation of each bit's two halves
// that depends on the bits above it, drawn from `seed` (Burley's hash, applied to the reversed bits).
inline uint32_t owen_scramble(uint32_t x, uint32_t seed) {
  x = reverse_bits(x);
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return reverse_bits(x);
}

// The first two dimensions of Sobol's sequence at `index`, as 32-bit fixed point: the van der
// Corput sequence (the index's bits reversed) and the second dimension (primitive polynomial x + 1,
// direction numbers v_0 = 2^31, v_k = v_(k-1) ^ (v_(k-1) >> 1)).
inline void sobol_2d_bits(uint32_t index, uint32_t& x, uint32_t& y) {
  x = reverse_bits(index);
  y = 0;
  for (uint32_t v = 0x80000000u; index != 0; index >>= 1, v ^= v >> 1)
    if (index & 1u) y ^= v;
}

// Point `index` of the Owen-scrambled sequence that `seed` picks, in [0, 1)^2.
inline Vec2 sobol_owen_2d(uint32_t index, uint64_t seed) {
  uint32_t x, y;
  sobol_2d_bits(index, x, y);
  const uint64_t h = mix64(seed);
  x = owen_scramble(x, static_cast<uint32_t>(h));
  y = owen_scramble(y, static_cast<uint32_t>(h >> 32));
  constexpr double kScale = 1.0 / 4294967296.0;  // 2^-32: the result stays below 1
  return Vec2(x * kScale, y * kScale);
}

}  // namespace ppm
