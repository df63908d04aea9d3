#include "shading/textures/gabor.h"

#include "shading/textures/hash.h"

#include <cmath>

namespace ppm::textures {
namespace {

constexpr int kImpulses = 8;  // per cell
constexpr float kPiF = static_cast<float>(kPi);

// One impulse at squared distance < 1 from its centre: the Hann-windowed Gaussian times the phasor
// of its sinusoid at `phase_angle`.
glm::vec2 kernel(float distance_squared, float phase_angle) {
  const float hann_window = 0.5f + 0.5f * std::cos(kPiF * distance_squared);
  const float envelope = std::exp(-kPiF * distance_squared) * hann_window;
  return envelope * glm::vec2(std::cos(phase_angle), std::sin(phase_angle));
}

glm::vec2 cell_2d(const glm::vec2& cell, const glm::vec2& p, float frequency, float isotropy, float base) {
  glm::vec2 sum(0.0f);
  for (int i = 0; i < kImpulses; ++i) {
    const float seed = float(i * 3);
    const float turn = (hash_float3_to_float(Vec3f(cell, seed)) - 0.5f) * kPiF;
    const float orientation = base + turn * isotropy;
    const glm::vec2 d = p - hash_float3_to_float2(Vec3f(cell, seed + 1.0f));
    const float distance_squared = glm::dot(d, d);
    if (distance_squared >= 1.0f) continue;
    const float weight = hash_float3_to_float(Vec3f(cell, seed + 2.0f)) < 0.5f ? -1.0f : 1.0f;
    const glm::vec2 direction = frequency * glm::vec2(std::cos(orientation), std::sin(orientation));
    sum += weight * kernel(distance_squared, 2.0f * kPiF * glm::dot(d, direction));
  }
  return sum;
}

// The base orientation turned at random (inclination and azimuth by up to pi each) by `isotropy`.
Vec3f orientation_3d(const Vec3f& base, float isotropy, const glm::vec4& seed) {
  if (isotropy == 0.0f) return base;
  float inclination = std::acos(base.z);
  const float planar = std::sqrt(base.x * base.x + base.y * base.y);  // 0 along z: Cycles' NaN, here 0
  float azimuth = planar > 0.0f ? (base.y < 0.0f ? -1.0f : 1.0f) * std::acos(base.x / planar) : 0.0f;
  const glm::vec2 angles = hash_float4_to_float2(seed) * kPiF;
  inclination += angles.x * isotropy;
  azimuth += angles.y * isotropy;
  return {std::sin(inclination) * std::cos(azimuth), std::sin(inclination) * std::sin(azimuth),
          std::cos(inclination)};
}

glm::vec2 cell_3d(const Vec3f& cell, const Vec3f& p, float frequency, float isotropy, const Vec3f& base) {
  glm::vec2 sum(0.0f);
  for (int i = 0; i < kImpulses; ++i) {
    const float seed = float(i * 3);
    const Vec3f orientation = orientation_3d(base, isotropy, glm::vec4(cell, seed));
    const Vec3f d = p - hash_float4_to_float3(glm::vec4(cell, seed + 1.0f));
    const float distance_squared = glm::dot(d, d);
    if (distance_squared >= 1.0f) continue;
    const float weight = hash_float4_to_float(glm::vec4(cell, seed + 2.0f)) < 0.5f ? -1.0f : 1.0f;
    sum += weight * kernel(distance_squared, 2.0f * kPiF * glm::dot(d, orientation * frequency));
  }
  return sum;
}

}  // namespace

GaborResult gabor(bool three_d, const Vec3f& p, float frequency, float anisotropy, float orientation_2d,
                  const Vec3f& orientation_3d_in) {
  const float isotropy = 1.0f - glm::clamp(anisotropy, 0.0f, 1.0f);
  frequency = std::max(0.001f, frequency);
  glm::vec2 phasor(0.0f);
  float deviation;  // of the noise, sqrt(impulses * second moment * integral of the kernel squared)
  if (three_d) {
    const Vec3f base = glm::normalize(orientation_3d_in);
    const Vec3f cell = glm::floor(p), local = p - cell;
    for (int k = -1; k <= 1; ++k)
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
          const Vec3f offset{float(i), float(j), float(k)};
          phasor += cell_3d(cell + offset, local - offset, frequency, isotropy, base);
        }
    deviation = std::sqrt(kImpulses * 0.5f * (1.0f / (4.0f * std::sqrt(2.0f))));
  } else {
    const glm::vec2 q(p.x, p.y), cell = glm::floor(q), local = q - cell;
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i) {
        const glm::vec2 offset{float(i), float(j)};
        phasor += cell_2d(cell + offset, local - offset, frequency, isotropy, orientation_2d);
      }
    deviation = std::sqrt(kImpulses * 0.5f * 0.25f);
  }
  const float normalisation = 6.0f * deviation;  // Blender's, found empirically
  GaborResult out;
  out.value = phasor.y / normalisation * 0.5f + 0.5f;
  out.phase = (std::atan2(phasor.y, phasor.x) + kPiF) / (2.0f * kPiF);
  out.intensity = glm::length(phasor) / normalisation;
  return out;
}

}  // namespace ppm::textures
