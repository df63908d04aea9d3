// Blender's Math, Vector Math, Map Range and Clamp nodes in float, with Cycles' safe variants
// (a division by zero gives 0, a square root of a negative number 0, ...), so that a node tree
// gives what it gives in Cycles.
#pragma once

#include "math/types.h"

#include <algorithm>
#include <cmath>

namespace ppm::nodes {

// The order of Blender's Math node operations as the exporter numbers them.
enum class MathOp : uint8_t {
  Add, Subtract, Multiply, Divide, MultiplyAdd, Power, Logarithm, Sqrt, InverseSqrt, Absolute,
  Exponent, Minimum, Maximum, LessThan, GreaterThan, Sign, Compare, SmoothMin, SmoothMax, Round,
  Floor, Ceil, Trunc, Fraction, Modulo, FlooredModulo, Wrap, Snap, PingPong, Sine, Cosine, Tangent,
  Arcsine, Arccosine, Arctangent, Arctan2, Sinh, Cosh, Tanh, Radians, Degrees,
};

enum class VectorMathOp : uint8_t {
  Add, Subtract, Multiply, Divide, MultiplyAdd, Cross, Project, Reflect, Refract, Faceforward,
  Dot, Distance, Length, Scale, Normalize, Snap, Floor, Ceil, Modulo, FlooredModulo, Wrap, Fraction,
  Absolute, Minimum, Maximum, Sine, Cosine, Tangent, Power, Sign,
};

inline float safe_divide(float a, float b) { return b != 0.0f ? a / b : 0.0f; }
inline float safe_modulo(float a, float b) { return b != 0.0f ? std::fmod(a, b) : 0.0f; }
inline float floored_modulo(float a, float b) { return b != 0.0f ? a - std::floor(a / b) * b : 0.0f; }
inline float fraction(float a) { return a - std::floor(a); }
inline float smooth_min(float a, float b, float k) {
  if (k == 0.0f) return std::min(a, b);
  const float h = std::max(k - std::fabs(a - b), 0.0f) / k;
  return std::min(a, b) - h * h * h * k * (1.0f / 6.0f);
}
inline float wrap(float v, float hi, float lo) {
  const float range = hi - lo;
  return range != 0.0f ? v - range * std::floor((v - lo) / range) : lo;
}
inline float snap(float a, float b) { return b != 0.0f ? std::floor(a / b) * b : 0.0f; }
inline float ping_pong(float a, float b) {
  return b != 0.0f ? std::fabs(fraction((a - b) / (b * 2.0f)) * b * 2.0f - b) : 0.0f;
}
inline float sign(float a) { return a > 0.0f ? 1.0f : (a < 0.0f ? -1.0f : 0.0f); }
// Cycles' safe_powf: a negative base to a non-integer power is 0.
inline float safe_pow(float a, float b) {
  if (a < 0.0f && b != std::trunc(b)) return 0.0f;
  return std::pow(a, b);
}
inline float safe_log(float a, float b) {
  if (a <= 0.0f || b <= 0.0f) return 0.0f;
  return safe_divide(std::log(a), std::log(b));
}

inline float math(MathOp op, float a, float b, float c) {
  switch (op) {
    case MathOp::Add: return a + b;
    case MathOp::Subtract: return a - b;
    case MathOp::Multiply: return a * b;
    case MathOp::Divide: return safe_divide(a, b);
    case MathOp::MultiplyAdd: return a * b + c;
    case MathOp::Power: return safe_pow(a, b);
    case MathOp::Logarithm: return safe_log(a, b);
    case MathOp::Sqrt: return a > 0.0f ? std::sqrt(a) : 0.0f;
    case MathOp::InverseSqrt: return a > 0.0f ? 1.0f / std::sqrt(a) : 0.0f;
    case MathOp::Absolute: return std::fabs(a);
    case MathOp::Exponent: return std::exp(a);
    case MathOp::Minimum: return std::fmin(a, b);
    case MathOp::Maximum: return std::fmax(a, b);
    case MathOp::LessThan: return a < b ? 1.0f : 0.0f;
    case MathOp::GreaterThan: return a > b ? 1.0f : 0.0f;
    case MathOp::Sign: return sign(a);
    case MathOp::Compare: return std::fabs(a - b) <= std::max(c, 1e-5f) ? 1.0f : 0.0f;
    case MathOp::SmoothMin: return smooth_min(a, b, c);
    case MathOp::SmoothMax: return -smooth_min(-a, -b, c);
    case MathOp::Round: return std::floor(a + 0.5f);
    case MathOp::Floor: return std::floor(a);
    case MathOp::Ceil: return std::ceil(a);
    case MathOp::Trunc: return std::trunc(a);
    case MathOp::Fraction: return fraction(a);
    case MathOp::Modulo: return safe_modulo(a, b);
    case MathOp::FlooredModulo: return floored_modulo(a, b);
    case MathOp::Wrap: return wrap(a, b, c);
    case MathOp::Snap: return snap(a, b);
    case MathOp::PingPong: return ping_pong(a, b);
    case MathOp::Sine: return std::sin(a);
    case MathOp::Cosine: return std::cos(a);
    case MathOp::Tangent: return std::tan(a);
    case MathOp::Arcsine: return std::asin(std::clamp(a, -1.0f, 1.0f));
    case MathOp::Arccosine: return std::acos(std::clamp(a, -1.0f, 1.0f));
    case MathOp::Arctangent: return std::atan(a);
    case MathOp::Arctan2: return std::atan2(a, b);
    case MathOp::Sinh: return std::sinh(a);
    case MathOp::Cosh: return std::cosh(a);
    case MathOp::Tanh: return std::tanh(a);
    case MathOp::Radians: return a * (static_cast<float>(kPi) / 180.0f);
    case MathOp::Degrees: return a * (180.0f / static_cast<float>(kPi));
  }
  return 0.0f;
}

template <class F>
Vec3f per_component(const Vec3f& a, const Vec3f& b, F&& f) {
  return Vec3f(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z));
}
inline Vec3f safe_normalize(const Vec3f& v) {
  const float l = glm::length(v);
  return l != 0.0f ? v / l : Vec3f(0.0f);
}
inline Vec3f refract(const Vec3f& incident, const Vec3f& normal, float eta) {
  const float k = 1.0f - eta * eta * (1.0f - glm::dot(normal, incident) * glm::dot(normal, incident));
  if (k < 0.0f) return Vec3f(0.0f);
  return eta * incident - (eta * glm::dot(normal, incident) + std::sqrt(k)) * normal;
}

struct VectorResult {
  Vec3f vector{0.0f};
  float value = 0.0f;
};

// `c` is the third vector input; `scale` the Scale input (Scale) or the IOR (Refract).
inline VectorResult vector_math(VectorMathOp op, const Vec3f& a, const Vec3f& b, const Vec3f& c, float scale) {
  VectorResult r;
  Vec3f& v = r.vector;
  switch (op) {
    case VectorMathOp::Add: v = a + b; break;
    case VectorMathOp::Subtract: v = a - b; break;
    case VectorMathOp::Multiply: v = a * b; break;
    case VectorMathOp::Divide: v = per_component(a, b, safe_divide); break;
    case VectorMathOp::MultiplyAdd: v = a * b + c; break;
    case VectorMathOp::Cross: v = glm::cross(a, b); break;
    case VectorMathOp::Project: {
      const float len2 = glm::dot(b, b);
      v = len2 != 0.0f ? b * (glm::dot(a, b) / len2) : Vec3f(0.0f);
      break;
    }
    case VectorMathOp::Reflect: {
      const Vec3f n = safe_normalize(b);
      v = a - 2.0f * glm::dot(n, a) * n;
      break;
    }
    case VectorMathOp::Refract: v = refract(a, safe_normalize(b), scale); break;
    case VectorMathOp::Faceforward: v = glm::dot(c, b) < 0.0f ? a : -a; break;
    case VectorMathOp::Dot: r.value = glm::dot(a, b); break;
    case VectorMathOp::Distance: r.value = glm::distance(a, b); break;
    case VectorMathOp::Length: r.value = glm::length(a); break;
    case VectorMathOp::Scale: v = a * scale; break;
    case VectorMathOp::Normalize: v = safe_normalize(a); break;
    case VectorMathOp::Snap: v = per_component(a, b, snap); break;
    case VectorMathOp::Floor: v = glm::floor(a); break;
    case VectorMathOp::Ceil: v = glm::ceil(a); break;
    case VectorMathOp::Modulo: v = per_component(a, b, safe_modulo); break;
    case VectorMathOp::FlooredModulo: v = per_component(a, b, floored_modulo); break;
    case VectorMathOp::Wrap: v = Vec3f(wrap(a.x, b.x, c.x), wrap(a.y, b.y, c.y), wrap(a.z, b.z, c.z)); break;
    case VectorMathOp::Fraction: v = a - glm::floor(a); break;
    case VectorMathOp::Absolute: v = glm::abs(a); break;
    case VectorMathOp::Minimum: v = glm::min(a, b); break;
    case VectorMathOp::Maximum: v = glm::max(a, b); break;
    case VectorMathOp::Sine: v = glm::sin(a); break;
    case VectorMathOp::Cosine: v = glm::cos(a); break;
    case VectorMathOp::Tangent: v = glm::tan(a); break;
    case VectorMathOp::Power: v = per_component(a, b, safe_pow); break;
    case VectorMathOp::Sign: v = Vec3f(sign(a.x), sign(a.y), sign(a.z)); break;
  }
  return r;
}

inline float smoothstep(float edge0, float edge1, float x) {
  if (x < edge0) return 0.0f;
  if (x >= edge1) return 1.0f;
  const float t = (x - edge0) / (edge1 - edge0);
  return (3.0f - 2.0f * t) * (t * t);
}

// Map Range: `mode` 0 linear, 1 stepped (`steps`), 2 smoothstep, 3 smootherstep.
inline float map_range(int mode, float value, float from_min, float from_max, float to_min, float to_max,
                       float steps, bool clamp) {
  float factor = 0.0f;
  if (from_max != from_min) {
    switch (mode) {
      case 0: factor = (value - from_min) / (from_max - from_min); break;
      case 1:
        factor = (value - from_min) / (from_max - from_min);
        factor = steps > 0.0f ? std::floor(factor * (steps + 1.0f)) / steps : 0.0f;
        break;
      case 2:
        factor = from_min > from_max ? 1.0f - smoothstep(from_max, from_min, value)
                                     : smoothstep(from_min, from_max, value);
        break;
      default: {
        const float t = from_min > from_max ? std::clamp((value - from_max) / (from_min - from_max), 0.0f, 1.0f)
                                            : std::clamp((value - from_min) / (from_max - from_min), 0.0f, 1.0f);
        const float s = t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
        factor = from_min > from_max ? 1.0f - s : s;
      }
    }
  }
  float result = to_min + factor * (to_max - to_min);
  if (clamp && mode < 2)
    result = to_max > to_min ? std::clamp(result, to_min, to_max) : std::clamp(result, to_max, to_min);
  return result;
}

// Blender's euler rotation (order XYZ: R = Rz Ry Rx), as the Mapping and Vector Rotate nodes use it.
inline glm::mat3 euler_to_matrix(const Vec3f& e) {
  const float cx = std::cos(e.x), sx = std::sin(e.x), cy = std::cos(e.y), sy = std::sin(e.y), cz = std::cos(e.z),
              sz = std::sin(e.z);
  return glm::mat3(cy * cz, cy * sz, -sy, sy * sx * cz - cx * sz, sy * sx * sz + cx * cz, cy * sx,
                   sy * cx * cz + sx * sz, sy * cx * sz - sx * cz, cy * cx);  // columns
}

inline Vec3f rotate_around_axis(const Vec3f& p, const Vec3f& axis, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return p * c + glm::cross(axis, p) * s + axis * glm::dot(axis, p) * (1.0f - c);
}

// Vector Rotate: `type` 0 about the Axis input, 1-3 about X, Y, Z, 4 by the euler Rotation.
inline Vec3f vector_rotate(int type, bool invert, const Vec3f& v, const Vec3f& center, const Vec3f& axis_in,
                           float angle, const Vec3f& euler) {
  if (type == 4) {
    const glm::mat3 r = euler_to_matrix(euler);
    return (invert ? glm::transpose(r) : r) * (v - center) + center;
  }
  const Vec3f axis = type == 0 ? safe_normalize(axis_in) : Vec3f(type == 1, type == 2, type == 3);
  if (axis == Vec3f(0.0f)) return v;
  return rotate_around_axis(v - center, axis, invert ? -angle : angle) + center;
}

}  // namespace ppm::nodes
