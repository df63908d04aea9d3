// Conversions between numpy arrays / Python values and core types, with the
// error messages that name the field and the object when the shape is wrong.
#pragma once

#include "base/utf8.h"
#include "math/types.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace ppm::py_convert {

namespace py = pybind11;

// Named channels of an (H, W, channels) float image, top row first, as a dict of views: a part of
// one channel is (H, W), of more (H, W, count). The values are copied once, into the views' base.
struct ChannelPart {
  const char* name;
  int first, count;
};
inline py::dict channel_views(int height, int width, const std::vector<float>& values, int channels,
                              std::initializer_list<ChannelPart> parts) {
  py::array_t<float> all({py::ssize_t(height), py::ssize_t(width), py::ssize_t(channels)}, values.data());
  const py::slice every(0, height, 1), columns(0, width, 1);
  py::dict out;
  for (const ChannelPart& part : parts) {
    if (part.count == 1)
      out[part.name] = all[py::make_tuple(every, columns, part.first)];
    else
      out[part.name] = all[py::make_tuple(every, columns, py::slice(part.first, part.first + part.count, 1))];
  }
  return out;
}
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

[[noreturn]] inline void fail(const std::string& what, const std::string& msg) {
  throw std::invalid_argument(what + ": " + msg);
}

// `obj` as a numpy array of Array's type (converted if need be), or a null
// array if it cannot be one, whether numpy says so by returning nothing or by
// raising: the caller reports what it expected.
template <class Array>
Array array_or_null(const py::handle& obj) {
  try {
    return Array::ensure(obj);
  } catch (const py::error_already_set&) {
    return py::reinterpret_steal<Array>(py::handle());
  }
}

// Numbers given as one value or a short list: as array_or_null, except that
// text is refused rather than parsed ("5" is not a size).
inline DoubleArray numbers_or_null(const py::handle& obj) {
  if (py::isinstance<py::str>(obj) || py::isinstance<py::bytes>(obj))
    return py::reinterpret_steal<DoubleArray>(py::handle());
  return array_or_null<DoubleArray>(obj);
}

// Strings arrive as str or bytes; bytes need not be UTF-8 (base/utf8.h: printable() makes them
// fit an error message).

// An object's name: any UTF-8 text (names end up in every error message).
inline const std::string& checked_name(const std::string& name, const std::string& kind) {
  if (!valid_utf8(name)) fail(kind + " '" + printable(name) + "'", "the name must be UTF-8 text");
  return name;
}

// An (N, cols) array of doubles; `what` and `field` name it in errors.
inline DoubleArray matrix(const py::handle& obj, int cols, const std::string& what, const std::string& field) {
  const DoubleArray a = array_or_null<DoubleArray>(obj);
  if (!a) fail(what, field + " must be an array of numbers");
  if (a.ndim() != 2 || a.shape(1) != cols)
    fail(what, field + " must have shape (N, " + std::to_string(cols) + ")");
  return a;
}

inline std::vector<Vec3> vec3_list(const py::handle& obj, const std::string& what, const std::string& field) {
  const DoubleArray a = matrix(obj, 3, what, field);
  std::vector<Vec3> out(a.shape(0));
  const double* p = a.data();
  for (size_t i = 0; i < out.size(); ++i) out[i] = Vec3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  return out;
}

inline std::vector<Vec2> vec2_list(const py::handle& obj, const std::string& what, const std::string& field) {
  const DoubleArray a = matrix(obj, 2, what, field);
  std::vector<Vec2> out(a.shape(0));
  const double* p = a.data();
  for (size_t i = 0; i < out.size(); ++i) out[i] = Vec2(p[2 * i], p[2 * i + 1]);
  return out;
}

inline Vec3 vec3(const py::handle& obj, const std::string& what, const std::string& field) {
  const DoubleArray a = array_or_null<DoubleArray>(obj);
  if (!a || a.size() != 3) fail(what, field + " must be 3 numbers");
  const double* p = a.data();
  return Vec3(p[0], p[1], p[2]);
}

// A colour: 3 numbers, or one number (a Python or numpy scalar, or a 1-element array) for grey.
inline Color color(const py::handle& obj, const std::string& what, const std::string& field) {
  if (py::isinstance<py::float_>(obj) || py::isinstance<py::int_>(obj)) return Color(obj.cast<double>());
  const DoubleArray a = numbers_or_null(obj);
  if (!a || (a.size() != 1 && a.size() != 3)) fail(what, field + " must be 3 numbers or one number (grey)");
  const double* p = a.data();
  return a.size() == 1 ? Color(p[0]) : Color(p[0], p[1], p[2]);
}

inline Mat4 mat4(const py::handle& obj, const std::string& what, const std::string& field) {
  const DoubleArray a = array_or_null<DoubleArray>(obj);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) fail(what, field + " must be a 4x4 matrix");
  const double* p = a.data();
  Mat4 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(p[4 * r + c])) fail(what, field + " contains NaN or Inf");
      m[c][r] = p[4 * r + c];  // numpy is row-major, glm column-major
    }
  return m;
}

// Strict enum from a lower-case name; the error lists the choices.
template <class E>
E choice(const std::string& value, std::initializer_list<std::pair<const char*, E>> options, const std::string& what,
         const std::string& field) {
  std::string names;
  for (const auto& [name, e] : options) {
    if (value == name) return e;
    names += (names.empty() ? "'" : ", '") + std::string(name) + "'";
  }
  fail(what, field + " must be one of " + names + ", not '" + printable(value) + "'");
}

}  // namespace ppm::py_convert
