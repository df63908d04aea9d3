// Random numbers: PCG32 (O'Neill 2014), seeded by a hash of (seed, stream, index)
// so every photon and every eye sample has its own stream. Results then depend
// on the seed only, not on which thread traced what.
#pragma once

#include <cstdint>

namespace ppm {

inline uint64_t mix64(uint64_t x) {  // splitmix64 finaliser
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  Rng(uint64_t seed, uint64_t stream, uint64_t index) {
    state_ = 0;
    inc_ = (mix64(stream * 0x632be59bd9b4e019ull ^ seed) << 1u) | 1u;
    next_u32();
    state_ += mix64(seed ^ mix64(index + 0x1234567ull * stream));
    next_u32();
  }

  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }

  // Uniform in [0, 1): 53 random bits from two draws.
  double uniform() {
    const uint64_t hi = next_u32() >> 5, lo = next_u32() >> 6;
    return static_cast<double>((hi << 26) | lo) * (1.0 / 9007199254740992.0);
  }

 private:
  uint64_t state_;
  uint64_t inc_;
};

}  // namespace ppm
