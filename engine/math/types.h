// Basic value types of the core: double-precision geometry (so one scene can
// span millimetres to kilometres), colours, and the scale-aware ray offset.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace ppm {

using Vec2 = glm::dvec2;
using Vec2f = glm::vec2;
using Vec3 = glm::dvec3;
using Vec3f = glm::vec3;
using Mat4 = glm::dmat4;
using Color = glm::dvec3;  // linear scene-referred RGB

constexpr double kPi = 3.14159265358979323846;
constexpr double kInvPi = 1.0 / kPi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// std::fmax's rule (a NaN argument is ignored), inline: GCC calls libm's
// fmax for std::fmax, and these run several times per ray.
inline double max_ignoring_nan(double a, double b) { return (a > b || b != b) ? a : b; }
inline double max_abs(const Vec3& v) {
  return max_ignoring_nan(std::fabs(v.x), max_ignoring_nan(std::fabs(v.y), std::fabs(v.z)));
}
inline double max_component(const Color& c) { return max_ignoring_nan(c.x, max_ignoring_nan(c.y, c.z)); }
// A finite value above float range saturates instead of becoming inf (the conversion is undefined
// behaviour in C++); NaN and inf stay visible.
inline float saturated_float(double v) {
  return std::isfinite(v) && std::fabs(v) > std::numeric_limits<float>::max()
             ? static_cast<float>(std::copysign(std::numeric_limits<float>::max(), v))
             : static_cast<float>(v);
}
inline double luminance(const Color& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
inline double mean(const Color& c) { return (c.x + c.y + c.z) / 3.0; }
inline bool is_finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Distance a new ray starts off a surface, along the geometric normal. Doubles
// carry ~1e-16 relative error, so 1e-9 of the point's magnitude clears acne with
// a wide margin while staying far below any modelled gap (a millimetre scene at
// 1 km from the origin still gets a 1e-6 m offset). `scene_floor` keeps the
// offset positive for points at the origin.
inline double ray_offset(const Vec3& p, double scene_floor) {
  return 1e-9 * max_abs(p) + scene_floor;
}

// Offset `p` to the side of the surface that `direction` leaves into.
inline Vec3 offset_point(const Vec3& p, const Vec3& geometric_normal, const Vec3& direction,
                         double scene_floor) {
  const double eps = ray_offset(p, scene_floor);
  return glm::dot(direction, geometric_normal) >= 0.0 ? p + eps * geometric_normal
                                                      : p - eps * geometric_normal;
}

// Orthonormal basis around a unit vector (Duff et al. 2017).
// Direction / length without overflow or underflow in the length; false for zero or non-finite.
inline bool unit_direction(const Vec3& v, Vec3& out) {
  const double m = max_abs(v);
  if (!(m > 0.0) || !std::isfinite(m)) return false;
  out = glm::normalize(v / m);
  return true;
}

inline void make_basis(const Vec3& n, Vec3& t, Vec3& b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double bb = n.x * n.y * a;
  t = Vec3(1.0 + sign * n.x * n.x * a, sign * bb, -sign * n.x);
  b = Vec3(bb, sign + n.y * n.y * a, -n.y);
}

}  // namespace ppm
