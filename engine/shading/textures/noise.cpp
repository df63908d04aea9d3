// Blender's Perlin noise and the textures built on it (see noise.h).
#include "shading/textures/noise.h"

#include "shading/textures/hash.h"

#include <algorithm>
#include <cmath>

namespace ppm::textures {
namespace {

float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
float negate_if(float v, uint32_t condition) { return condition != 0 ? -v : v; }
float floor_frac(float x, int& i) {
  const float f = std::floor(x);
  i = to_int(f);
  return x - f;
}
float lerp(float a, float b, float t) { return (1.0f - t) * a + t * b; }

// Gradients: Perlin's improved noise's edge directions, picked by the low bits of the hash.
float grad1(uint32_t hash, float x) {
  const uint32_t h = hash & 15u;
  return negate_if(1.0f + float(h & 7u), h & 8u) * x;
}
float grad2(uint32_t hash, float x, float y) {
  const uint32_t h = hash & 7u;
  const float u = h < 4 ? x : y, v = 2.0f * (h < 4 ? y : x);
  return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}
float grad3(uint32_t hash, float x, float y, float z) {
  const uint32_t h = hash & 15u;
  const float u = h < 8 ? x : y;
  const float vt = (h == 12 || h == 14) ? x : z;
  const float v = h < 4 ? y : vt;
  return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}
float grad4(uint32_t hash, float x, float y, float z, float w) {
  const uint32_t h = hash & 31u;
  const float u = h < 24 ? x : y, v = h < 16 ? y : z, s = h < 8 ? z : w;
  return negate_if(u, h & 1u) + negate_if(v, h & 2u) + negate_if(s, h & 4u);
}

float bi_mix(float v0, float v1, float v2, float v3, float x, float y) {
  const float x1 = 1.0f - x;
  return (1.0f - y) * (v0 * x1 + v1 * x) + y * (v2 * x1 + v3 * x);
}
float tri_mix(const float v[8], float x, float y, float z) {
  const float x1 = 1.0f - x, y1 = 1.0f - y, z1 = 1.0f - z;
  return z1 * (y1 * (v[0] * x1 + v[1] * x) + y * (v[2] * x1 + v[3] * x)) +
         z * (y1 * (v[4] * x1 + v[5] * x) + y * (v[6] * x1 + v[7] * x));
}

uint32_t u(int i) { return static_cast<uint32_t>(i); }

float perlin(float x) {
  int X;
  const float fx = floor_frac(x, X);
  return lerp(grad1(hash_uint(u(X)), fx), grad1(hash_uint(u(X + 1)), fx - 1.0f), fade(fx));
}

float perlin(float x, float y) {
  int X, Y;
  const float fx = floor_frac(x, X), fy = floor_frac(y, Y);
  return bi_mix(grad2(hash_uint2(u(X), u(Y)), fx, fy), grad2(hash_uint2(u(X + 1), u(Y)), fx - 1.0f, fy),
                grad2(hash_uint2(u(X), u(Y + 1)), fx, fy - 1.0f),
                grad2(hash_uint2(u(X + 1), u(Y + 1)), fx - 1.0f, fy - 1.0f), fade(fx), fade(fy));
}

float perlin(float x, float y, float z) {
  int X, Y, Z;
  const float fx = floor_frac(x, X), fy = floor_frac(y, Y), fz = floor_frac(z, Z);
  float v[8];
  for (int k = 0; k < 8; ++k) {
    const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
    v[k] = grad3(hash_uint3(u(X + dx), u(Y + dy), u(Z + dz)), fx - dx, fy - dy, fz - dz);
  }
  return tri_mix(v, fade(fx), fade(fy), fade(fz));
}

float perlin(float x, float y, float z, float w) {
  int X, Y, Z, W;
  const float fx = floor_frac(x, X), fy = floor_frac(y, Y), fz = floor_frac(z, Z), fw = floor_frac(w, W);
  float v[16];
  for (int k = 0; k < 16; ++k) {
    const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1, dw = (k >> 3) & 1;
    v[k] = grad4(hash_uint4(u(X + dx), u(Y + dy), u(Z + dz), u(W + dw)), fx - dx, fy - dy, fz - dz, fw - dw);
  }
  const float a = fade(fx), b = fade(fy), c = fade(fz);
  return lerp(tri_mix(v, a, b, c), tri_mix(v + 8, a, b, c), fade(fw));
}

// Far from the origin Cycles wraps coordinates (noise repeats every 100000 units) and, beyond a
// million, moves them half a cell, where float noise would otherwise be constant.
float precise(float p) { return std::fmod(p, 100000.0f) + (std::fabs(p) >= 1000000.0f ? 0.5f : 0.0f); }

// Cycles' offsets that decorrelate distortion and colour channels.
glm::vec4 random_offset4(float seed) {
  glm::vec4 o;
  for (int k = 0; k < 4; ++k) o[k] = 100.0f + hash_float2_to_float(seed, float(k)) * 100.0f;
  return o;
}
float random_offset1(float seed) { return 100.0f + hash_float_to_float(seed) * 100.0f; }

// Noise of `dims` dimensions at the first `dims` components of p.
float snoise_n(int dims, const glm::vec4& p) {
  switch (dims) {
    case 1: return snoise(p.x);
    case 2: return snoise(Vec2f(p.x, p.y));
    case 3: return snoise(Vec3f(p));
    default: return snoise(p);
  }
}
glm::vec4 offset(int dims, float seed) {
  if (dims == 1) return glm::vec4(random_offset1(seed), 0.0f, 0.0f, 0.0f);
  glm::vec4 o = random_offset4(seed);
  for (int k = dims; k < 4; ++k) o[k] = 0.0f;
  return o;
}

float fbm_legacy(int dims, const glm::vec4& p, float octaves, float roughness) {
  float scale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
  octaves = std::isfinite(octaves) ? std::clamp(octaves, 0.0f, 15.0f) : 0.0f;
  const int n = to_int(octaves);
  roughness = std::clamp(roughness, 0.0f, 1.0f);
  for (int i = 0; i <= n; ++i) {
    sum += (0.5f * snoise_n(dims, scale * p) + 0.5f) * amp;
    maxamp += amp;
    amp *= roughness;
    scale *= 2.0f;
  }
  const float rmd = octaves - std::floor(octaves);
  if (rmd == 0.0f) return sum / maxamp;
  const float sum2 = sum + (0.5f * snoise_n(dims, scale * p) + 0.5f) * amp;
  return (1.0f - rmd) * (sum / maxamp) + rmd * (sum2 / (maxamp + amp));
}

float fbm(int dims, const glm::vec4& p, float detail, float roughness, float lacunarity, bool normalize) {
  float scale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
  for (int i = 0; i <= to_int(detail); ++i) {
    sum += snoise_n(dims, scale * p) * amp;
    maxamp += amp;
    amp *= roughness;
    scale *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd == 0.0f) return normalize ? 0.5f * sum / maxamp + 0.5f : sum;
  const float sum2 = sum + snoise_n(dims, scale * p) * amp;
  if (!normalize) return lerp(sum, sum2, rmd);
  return lerp(0.5f * sum / maxamp + 0.5f, 0.5f * sum2 / (maxamp + amp) + 0.5f, rmd);
}

float multifractal(int dims, glm::vec4 p, float detail, float roughness, float lacunarity) {
  float value = 1.0f, pwr = 1.0f;
  for (int i = 0; i <= to_int(detail); ++i) {
    value *= pwr * snoise_n(dims, p) + 1.0f;
    pwr *= roughness;
    p *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd != 0.0f) value *= rmd * pwr * snoise_n(dims, p) + 1.0f;
  return value;
}

float hetero_terrain(int dims, glm::vec4 p, float detail, float roughness, float lacunarity, float offset) {
  float pwr = roughness;
  float value = offset + snoise_n(dims, p);
  p *= lacunarity;
  for (int i = 1; i <= to_int(detail); ++i) {
    value += (snoise_n(dims, p) + offset) * pwr * value;
    pwr *= roughness;
    p *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd != 0.0f) value += rmd * ((snoise_n(dims, p) + offset) * pwr * value);
  return value;
}

float hybrid_multifractal(int dims, glm::vec4 p, float detail, float roughness, float lacunarity, float offset,
                          float gain) {
  float pwr = 1.0f, value = 0.0f, weight = 1.0f;
  for (int i = 0; weight > 0.001f && i <= to_int(detail); ++i) {
    weight = std::min(weight, 1.0f);
    const float signal = (snoise_n(dims, p) + offset) * pwr;
    pwr *= roughness;
    value += weight * signal;
    weight *= gain * signal;
    p *= lacunarity;
  }
  const float rmd = detail - std::floor(detail);
  if (rmd != 0.0f && weight > 0.001f) {
    weight = std::min(weight, 1.0f);
    value += rmd * weight * ((snoise_n(dims, p) + offset) * pwr);
  }
  return value;
}

float ridged_multifractal(int dims, glm::vec4 p, float detail, float roughness, float lacunarity, float offset,
                          float gain) {
  float pwr = roughness;
  float signal = offset - std::fabs(snoise_n(dims, p));
  signal *= signal;
  float value = signal, weight = 1.0f;
  for (int i = 1; i <= to_int(detail); ++i) {
    p *= lacunarity;
    weight = std::clamp(signal * gain, 0.0f, 1.0f);
    signal = offset - std::fabs(snoise_n(dims, p));
    signal *= signal * weight;
    value += signal * pwr;
    pwr *= roughness;
  }
  return value;
}

float noise_select(const NoiseSettings& s, const glm::vec4& p) {
  if (s.legacy) return fbm_legacy(s.dimensions, p, s.detail, s.roughness);
  switch (s.type) {
    case NoiseType::Fbm: return fbm(s.dimensions, p, s.detail, s.roughness, s.lacunarity, s.normalize);
    case NoiseType::Multifractal: return multifractal(s.dimensions, p, s.detail, s.roughness, s.lacunarity);
    case NoiseType::HybridMultifractal:
      return hybrid_multifractal(s.dimensions, p, s.detail, s.roughness, s.lacunarity, s.offset, s.gain);
    case NoiseType::RidgedMultifractal:
      return ridged_multifractal(s.dimensions, p, s.detail, s.roughness, s.lacunarity, s.offset, s.gain);
    case NoiseType::HeteroTerrain:
      return hetero_terrain(s.dimensions, p, s.detail, s.roughness, s.lacunarity, s.offset);
  }
  return 0.0f;
}

}  // namespace

float snoise(float p) { return 0.2500f * perlin(precise(p)); }
float snoise(const Vec2f& p) { return 0.6616f * perlin(precise(p.x), precise(p.y)); }
float snoise(const Vec3f& p) { return 0.9820f * perlin(precise(p.x), precise(p.y), precise(p.z)); }
float snoise(const glm::vec4& p) { return 0.8344f * perlin(precise(p.x), precise(p.y), precise(p.z), precise(p.w)); }

NoiseResult noise_texture(const NoiseSettings& settings, const glm::vec4& point, bool with_color) {
  NoiseSettings s = settings;
  s.detail = std::isfinite(s.detail) ? std::clamp(s.detail, 0.0f, 15.0f) : 0.0f;
  s.roughness = std::max(s.roughness, 0.0f);
  const int dims = s.dimensions;
  glm::vec4 p = point;
  for (int k = dims; k < 4; ++k) p[k] = 0.0f;
  if (s.distortion != 0.0f) {
    glm::vec4 shift(0.0f);
    for (int k = 0; k < dims; ++k) shift[k] = snoise_n(dims, p + offset(dims, float(k))) * s.distortion;
    p += shift;
  }
  NoiseResult r;
  r.fac = noise_select(s, p);
  if (with_color)
    r.color = Vec3f(r.fac, noise_select(s, p + offset(dims, float(dims))),
                    noise_select(s, p + offset(dims, float(dims + 1))));
  return r;
}

float musgrave_texture(const NoiseSettings& settings, glm::vec4 p) {
  const int dims = settings.dimensions;
  const float h = std::max(settings.roughness, 1e-5f);  // Musgrave's Dimension
  const float lacunarity = std::max(settings.lacunarity, 1e-5f);
  const float octaves = std::isfinite(settings.detail) ? std::clamp(settings.detail, 0.0f, 15.0f) : 0.0f;
  const float offset = settings.offset, gain = settings.gain;
  const float pw_hl = std::pow(lacunarity, -h);
  const int n = to_int(octaves);
  const float rmd = octaves - std::floor(octaves);
  float value = 0.0f, pwr = 1.0f;
  switch (settings.type) {
    case NoiseType::Fbm:
      for (int i = 0; i < n; ++i, pwr *= pw_hl, p *= lacunarity) value += snoise_n(dims, p) * pwr;
      if (rmd != 0.0f) value += rmd * snoise_n(dims, p) * pwr;
      return value;
    case NoiseType::Multifractal:
      value = 1.0f;
      for (int i = 0; i < n; ++i, pwr *= pw_hl, p *= lacunarity) value *= pwr * snoise_n(dims, p) + 1.0f;
      if (rmd != 0.0f) value *= rmd * pwr * snoise_n(dims, p) + 1.0f;
      return value;
    case NoiseType::HeteroTerrain:
      pwr = pw_hl;
      value = offset + snoise_n(dims, p);
      p *= lacunarity;
      for (int i = 1; i < n; ++i, pwr *= pw_hl, p *= lacunarity) value += (snoise_n(dims, p) + offset) * pwr * value;
      if (rmd != 0.0f) value += rmd * (snoise_n(dims, p) + offset) * pwr * value;
      return value;
    case NoiseType::HybridMultifractal: {
      float weight = 1.0f;
      for (int i = 0; weight > 0.001f && i < n; ++i) {
        weight = std::min(weight, 1.0f);
        const float signal = (snoise_n(dims, p) + offset) * pwr;
        pwr *= pw_hl;
        value += weight * signal;
        weight *= gain * signal;
        p *= lacunarity;
      }
      if (rmd != 0.0f && weight > 0.001f) value += rmd * std::min(weight, 1.0f) * (snoise_n(dims, p) + offset) * pwr;
      return value;
    }
    case NoiseType::RidgedMultifractal: {
      pwr = pw_hl;
      float signal = offset - std::fabs(snoise_n(dims, p));
      signal *= signal;
      value = signal;
      for (int i = 1; i < n; ++i) {
        p *= lacunarity;
        const float weight = std::clamp(signal * gain, 0.0f, 1.0f);
        signal = offset - std::fabs(snoise_n(dims, p));
        signal *= signal * weight;
        value += signal * pwr;
        pwr *= pw_hl;
      }
      return value;
    }
  }
  return 0.0f;
}

float fractal_noise_legacy(const Vec3f& p, float detail, float roughness) {
  return fbm_legacy(3, glm::vec4(p, 0.0f), detail, roughness);
}
float fractal_noise_fbm(const Vec3f& p, float detail, float roughness, float lacunarity, bool normalize) {
  // Detail counts octaves: Blender's sockets stop at 15, a script's value may not (10^30 octaves
  // would never end).
  detail = std::isfinite(detail) ? std::clamp(detail, 0.0f, 15.0f) : 0.0f;
  return fbm(3, glm::vec4(p, 0.0f), detail, roughness, lacunarity, normalize);
}

WhiteNoiseResult white_noise(int dims, const glm::vec4& p) {
  WhiteNoiseResult r;
  switch (dims) {
    case 1:
      r.value = hash_float_to_float(p.x);
      r.color = Vec3f(r.value, hash_float2_to_float(p.x, 1.0f), hash_float2_to_float(p.x, 2.0f));
      break;
    case 2:
      r.value = hash_float2_to_float(p.x, p.y);
      r.color = Vec3f(r.value, hash_float3_to_float(Vec3f(p.x, p.y, 1.0f)),
                      hash_float3_to_float(Vec3f(p.x, p.y, 2.0f)));
      break;
    case 3:
      r.value = hash_float3_to_float(Vec3f(p));
      r.color = Vec3f(r.value, hash_float4_to_float(glm::vec4(p.x, p.y, p.z, 1.0f)),
                      hash_float4_to_float(glm::vec4(p.x, p.y, p.z, 2.0f)));
      break;
    default:
      r.value = hash_float4_to_float(p);
      r.color = Vec3f(r.value, hash_float4_to_float(glm::vec4(p.z, p.x, p.w, p.y)),
                      hash_float4_to_float(glm::vec4(p.w, p.z, p.y, p.x)));
  }
  return r;
}

}  // namespace ppm::textures
