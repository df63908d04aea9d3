// The hashes Blender's procedural textures are built on: Bob Jenkins' lookup3 on 1 to 4 unsigned
// words (its `mix` and `final` mixing), and floats hashed by their bit patterns. Reproducing them
// bit for bit is what makes a Noise or Voronoi texture line up with Cycles'.
#pragma once

#include "math/types.h"

#include <cstdint>
#include <cmath>
#include <cstring>

namespace ppm::textures {

// float -> int as C's cast does for the values Blender's textures meet, but defined for every float
// (NaN gives 0; beyond int's range, its ends), since node values can be anything.
inline int to_int(float x) {
  if (!(x == x)) return 0;
  return static_cast<int>(std::fmax(std::fmin(x, 2147483520.0f), -2147483520.0f));
}

inline uint32_t rotate(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

inline void lookup3_mix(uint32_t& a, uint32_t& b, uint32_t& c) {
  a -= c; a ^= rotate(c, 4); c += b;
  b -= a; b ^= rotate(a, 6); a += c;
  c -= b; c ^= rotate(b, 8); b += a;
  a -= c; a ^= rotate(c, 16); c += b;
  b -= a; b ^= rotate(a, 19); a += c;
  c -= b; c ^= rotate(b, 4); b += a;
}

inline void lookup3_final(uint32_t& a, uint32_t& b, uint32_t& c) {
  c ^= b; c -= rotate(b, 14);
  a ^= c; a -= rotate(c, 11);
  b ^= a; b -= rotate(a, 25);
  c ^= b; c -= rotate(b, 16);
  a ^= c; a -= rotate(c, 4);
  b ^= a; b -= rotate(a, 14);
  c ^= b; c -= rotate(b, 24);
}

constexpr uint32_t lookup3_seed(uint32_t words) { return 0xdeadbeefu + (words << 2) + 13u; }

inline uint32_t hash_uint(uint32_t kx) {
  uint32_t a = lookup3_seed(1), b = a, c = a;
  a += kx;
  lookup3_final(a, b, c);
  return c;
}
inline uint32_t hash_uint2(uint32_t kx, uint32_t ky) {
  uint32_t a = lookup3_seed(2), b = a, c = a;
  b += ky;
  a += kx;
  lookup3_final(a, b, c);
  return c;
}
inline uint32_t hash_uint3(uint32_t kx, uint32_t ky, uint32_t kz) {
  uint32_t a = lookup3_seed(3), b = a, c = a;
  c += kz;
  b += ky;
  a += kx;
  lookup3_final(a, b, c);
  return c;
}
inline uint32_t hash_uint4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
  uint32_t a = lookup3_seed(4), b = a, c = a;
  a += kx;
  b += ky;
  c += kz;
  lookup3_mix(a, b, c);
  a += kw;
  lookup3_final(a, b, c);
  return c;
}

inline uint32_t bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
inline float uint_to_unit(uint32_t k) { return float(k) / float(0xFFFFFFFFu); }

inline float hash_float_to_float(float k) { return uint_to_unit(hash_uint(bits(k))); }
inline float hash_float2_to_float(float x, float y) { return uint_to_unit(hash_uint2(bits(x), bits(y))); }
inline float hash_float3_to_float(const Vec3f& k) { return uint_to_unit(hash_uint3(bits(k.x), bits(k.y), bits(k.z))); }
inline float hash_float4_to_float(const glm::vec4& k) {
  return uint_to_unit(hash_uint4(bits(k.x), bits(k.y), bits(k.z), bits(k.w)));
}
// Blender's hash_float{3,4}_to_float{2,3}: the same key hashed with its components shuffled.
inline glm::vec2 hash_float3_to_float2(const Vec3f& k) {
  return {hash_float3_to_float(k), hash_float3_to_float(Vec3f(k.z, k.x, k.y))};
}
inline glm::vec2 hash_float4_to_float2(const glm::vec4& k) {
  return {hash_float4_to_float(k), hash_float4_to_float(glm::vec4(k.z, k.x, k.w, k.y))};
}
inline Vec3f hash_float4_to_float3(const glm::vec4& k) {
  return {hash_float4_to_float(k), hash_float4_to_float(glm::vec4(k.z, k.x, k.w, k.y)),
          hash_float4_to_float(glm::vec4(k.w, k.z, k.y, k.x))};
}

// PCG hashes of integer vectors (Jarzynski and Olano 2020, in Blender's signed-integer form): newer
// Blender's Voronoi hashes its cells with these. Arithmetic wraps; `>>` keeps the sign.
template <int N>
glm::vec<N, int32_t> hash_pcg(glm::vec<N, int32_t> v) {
  auto wrap = [](int64_t x) { return static_cast<int32_t>(static_cast<uint32_t>(x)); };
  auto mul = [&](int32_t a, int32_t b) { return wrap(int64_t(uint32_t(a)) * int64_t(uint32_t(b))); };
  auto add = [&](int32_t a, int32_t b) { return wrap(int64_t(uint32_t(a)) + int64_t(uint32_t(b))); };
  for (int i = 0; i < N; ++i) v[i] = add(mul(v[i], 1664525), 1013904223);
  auto mix = [&] {
    if constexpr (N == 2) {
      v.x = add(v.x, mul(v.y, 1664525));
      v.y = add(v.y, mul(v.x, 1664525));
    } else if constexpr (N == 3) {
      v.x = add(v.x, mul(v.y, v.z));
      v.y = add(v.y, mul(v.z, v.x));
      v.z = add(v.z, mul(v.x, v.y));
    } else {
      v.x = add(v.x, mul(v.y, v.w));
      v.y = add(v.y, mul(v.z, v.x));
      v.z = add(v.z, mul(v.x, v.y));
      v.w = add(v.w, mul(v.y, v.z));
    }
  };
  mix();
  for (int i = 0; i < N; ++i) v[i] = v[i] ^ (v[i] >> 16);
  mix();
  return v;
}

// Blender's hash_int{2,3,4}_to_vec{2,3,4}: components in [0, 1].
template <int N>
glm::vec<N, float> hash_int_to_unit(const glm::vec<N, int32_t>& k) {
  const glm::vec<N, int32_t> h = hash_pcg<N>(k);
  glm::vec<N, float> out;
  for (int i = 0; i < N; ++i) out[i] = float(h[i] & 0x7fffffff) * (1.0f / float(0x7fffffff));
  return out;
}

template <int N>
glm::vec<N, int32_t> to_ints(const glm::vec<N, float>& v) {
  glm::vec<N, int32_t> out;
  for (int i = 0; i < N; ++i) out[i] = to_int(v[i]);
  return out;
}

}  // namespace ppm::textures
