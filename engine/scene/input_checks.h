// What the scene's builders check of their input: each check throws std::invalid_argument that
// names the object ("mesh 'Cube'") and the field. Shared by the files that implement Scene.
#pragma once

#include "math/types.h"
#include "scene/scene.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ppm {
namespace scene_input {

[[noreturn]] inline void fail(const std::string& what, const std::string& message) {
  throw std::invalid_argument(what + ": " + message);
}

inline std::string quoted(const std::string& kind, const std::string& name) {
  return kind + " '" + name + "'";
}

inline std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

inline void check_finite(const Vec3& v, const std::string& what, const std::string& field) {
  if (!is_finite(v)) fail(what, field + " is not finite (NaN or Inf)");
}
inline void check_finite(const Color& c, double lo, const std::string& what, const std::string& field) {
  check_finite(Vec3(c), what, field);
  if (c.x < lo || c.y < lo || c.z < lo) fail(what, field + " has a negative component");
}
// A point or offset in metres: finite and within kMaxCoordinate.
inline void check_coordinates(const Vec3& v, const std::string& what, const std::string& field) {
  check_finite(v, what, field);
  if (max_abs(v) > kMaxCoordinate)
    fail(what, field + " has a component of magnitude " + number(max_abs(v)) + ", above the supported " +
                   number(kMaxCoordinate) + " m");
}
// Light power, irradiance or radiance: finite, >= 0 and at most kMaxPower.
// Cycles' range for a light's Max Bounces.
inline void check_max_bounces(int max_bounces, const std::string& what) {
  if (max_bounces < 0 || max_bounces > 1024) fail(what, "max_bounces must be in [0, 1024]");
}

inline void check_power(const Color& c, const std::string& what, const std::string& field) {
  check_finite(c, 0.0, what, field);
  if (max_component(c) > kMaxPower)
    fail(what, field + " " + number(max_component(c)) + " is above the supported " + number(kMaxPower));
}
// A radius or size in metres: in [kMinSize, kMaxCoordinate].
inline void check_size(double x, const std::string& what, const std::string& field) {
  if (!std::isfinite(x) || x <= 0.0) fail(what, field + " must be a positive number");
  if (x < kMinSize || x > kMaxCoordinate)
    fail(what, field + " " + number(x) + " is outside the supported range [" + number(kMinSize) + ", " +
                   number(kMaxCoordinate) + "] m");
}

// v / |v| without overflow or underflow in |v|^2; false for a zero or non-finite v.
inline bool safe_normalize(const Vec3& v, Vec3& out) {
  const double m = max_abs(v);
  if (!(m > 0.0) || !std::isfinite(m)) return false;
  const Vec3 s = v / m;
  out = s / glm::length(s);
  return true;
}


}  // namespace scene_input
}  // namespace ppm
