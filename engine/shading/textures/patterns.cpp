// Blender's pattern textures (see patterns.h).
#include "shading/textures/patterns.h"

#include "shading/textures/hash.h"
#include "shading/textures/noise.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ppm::textures {
namespace {

constexpr float kTwoPi = 6.2831853071795864f;
constexpr float kHalfPi = 1.5707963267948966f;

// Cycles nudges coordinates off exact cell boundaries before these patterns.
Vec3f nudged(const Vec3f& p) { return (p + Vec3f(0.000001f)) * 0.999999f; }

float brick_noise(uint32_t n) {
  n = (n + 1013u) & 0x7fffffffu;
  n = (n >> 13) ^ n;
  const uint32_t nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
  return 0.5f * (float(nn) / 1073741824.0f);
}

float smoothstep01(float f) {
  if (f <= 0.0f) return 0.0f;
  if (f >= 1.0f) return 1.0f;
  return 3.0f * f * f - 2.0f * f * f * f;
}

}  // namespace

float checker(Vec3f p) {
  p = nudged(p);
  const int xi = std::abs(to_int(std::floor(p.x)));
  const int yi = std::abs(to_int(std::floor(p.y)));
  const int zi = std::abs(to_int(std::floor(p.z)));
  return ((xi % 2 == yi % 2) == (zi % 2 != 0)) ? 1.0f : 0.0f;
}

float gradient(GradientType type, const Vec3f& p) {
  float g = 0.0f;
  switch (type) {
    case GradientType::Linear: g = p.x; break;
    case GradientType::Quadratic: {
      const float r = std::max(p.x, 0.0f);
      g = r * r;
      break;
    }
    case GradientType::Easing: {
      const float r = std::clamp(p.x, 0.0f, 1.0f), t = r * r;
      g = 3.0f * t - 2.0f * t * r;
      break;
    }
    case GradientType::Diagonal: g = (p.x + p.y) * 0.5f; break;
    case GradientType::Radial: g = std::atan2(p.y, p.x) / kTwoPi + 0.5f; break;
    case GradientType::QuadraticSphere: {
      const float r = std::max(0.999999f - std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), 0.0f);
      g = r * r;
      break;
    }
    case GradientType::Spherical: g = std::max(0.999999f - std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), 0.0f); break;
  }
  return std::clamp(g, 0.0f, 1.0f);
}

float wave(const WaveSettings& s, Vec3f p) {
  p = nudged(p);
  float n;
  if (s.kind == 0) {
    n = s.direction == 3 ? (p.x + p.y + p.z) * 10.0f : p[std::min<int>(s.direction, 2)] * 20.0f;
  } else {
    Vec3f rp = p;
    if (s.direction < 3) rp[s.direction] = 0.0f;
    n = std::sqrt(rp.x * rp.x + rp.y * rp.y + rp.z * rp.z) * 20.0f;
  }
  n += s.phase;
  if (s.distortion != 0.0f) {
    const float fbm = s.legacy ? fractal_noise_legacy(p * s.detail_scale, s.detail, s.detail_roughness)
                               : fractal_noise_fbm(p * s.detail_scale, s.detail, s.detail_roughness, 2.0f, true);
    n += s.distortion * (fbm * 2.0f - 1.0f);
  }
  if (s.profile == 0) return 0.5f + 0.5f * std::sin(n - kHalfPi);
  n /= kTwoPi;
  if (s.profile == 1) return n - std::floor(n);
  return std::fabs(n - std::floor(n + 0.5f)) * 2.0f;
}

Vec3f magic(const Vec3f& vector, float scale, int depth, float d, bool wrapped) {
  float x, y, z;
  if (wrapped) {
    const float px = std::fmod(vector.x, kTwoPi), py = std::fmod(vector.y, kTwoPi), pz = std::fmod(vector.z, kTwoPi);
    x = std::sin((px + py + pz) * 5.0f * scale);
    y = std::cos((-px + py - pz) * 5.0f * scale);
    z = -std::cos((-px - py + pz) * 5.0f * scale);
  } else {
    const Vec3f p = vector * scale;
    x = std::sin((p.x + p.y + p.z) * 5.0f);
    y = std::cos((-p.x + p.y - p.z) * 5.0f);
    z = -std::cos((-p.x - p.y + p.z) * 5.0f);
  }
  if (depth > 0) {
    x *= d, y *= d, z *= d;
    y = -std::cos(x - y + z) * d;
    if (depth > 1) x = std::cos(x - y - z) * d;
    if (depth > 2) z = std::sin(-x - y - z) * d;
    if (depth > 3) x = -std::cos(-x + y - z) * d;
    if (depth > 4) y = -std::sin(-x + y + z) * d;
    if (depth > 5) y = -std::cos(-x + y + z) * d;
    if (depth > 6) x = std::cos(x + y + z) * d;
    if (depth > 7) z = std::sin(x + y - z) * d;
    if (depth > 8) x = -std::cos(-x - y + z) * d;
    if (depth > 9) y = -std::sin(x - y + z) * d;
  }
  if (d != 0.0f) {
    d *= 2.0f;
    x /= d, y /= d, z /= d;
  }
  return Vec3f(0.5f - x, 0.5f - y, 0.5f - z);
}

BrickResult brick(const BrickSettings& s, const Vec3f& p) {
  float brick_width = s.brick_width, offset = 0.0f;
  const int row = to_int(std::floor(p.y / s.row_height));
  if (s.offset_frequency != 0 && s.squash_frequency != 0) {
    brick_width *= (row % s.squash_frequency) != 0 ? 1.0f : s.squash;
    offset = (row % s.offset_frequency) != 0 ? 0.0f : brick_width * s.offset;
  }
  const int column = to_int(std::floor((p.x + offset) / brick_width));
  const float x = (p.x + offset) - brick_width * float(column), y = p.y - s.row_height * float(row);
  BrickResult r;
  const uint32_t key = (static_cast<uint32_t>(row) << 16) + (static_cast<uint32_t>(column) & 0xFFFFu);
  r.tint = std::clamp(brick_noise(key) + s.bias, 0.0f, 1.0f);
  const float edge = std::min(std::min(x, y), std::min(brick_width - x, s.row_height - y));
  if (edge >= s.mortar_size) r.mortar = 0.0f;
  else if (s.mortar_smooth == 0.0f) r.mortar = 1.0f;
  else r.mortar = smoothstep01((1.0f - edge / s.mortar_size) / s.mortar_smooth);
  return r;
}

}  // namespace ppm::textures
