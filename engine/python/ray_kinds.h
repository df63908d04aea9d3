// Ray kinds by name (geometry/ray.h), and what an object, light or world is visible to.
#pragma once

#include "geometry/ray.h"
#include "python/convert.h"

#include <string>

namespace ppm::py_convert {

inline const std::initializer_list<std::pair<const char*, uint8_t>> kRayKindNames = {
    {"camera", kCameraRay}, {"diffuse", kDiffuseRay}, {"glossy", kGlossyRay},
    {"transmission", kTransmissionRay}, {"shadow", kShadowRay}};

// The RayKinds an object or light is visible to: None (all), or names from kRayKindNames.
inline uint8_t visibility(const py::object& names, const std::string& what) {
  if (names.is_none()) return kAllRayKinds;
  if (py::isinstance<py::str>(names) || !py::isinstance<py::iterable>(names))
    fail(what, "visibility must be None or a list of ray kinds (camera, diffuse, glossy, transmission, shadow)");
  uint8_t mask = 0;
  for (const py::handle name : names) {
    if (!py::isinstance<py::str>(name)) fail(what, "visibility must name ray kinds as strings");
    mask |= choice<uint8_t>(py::cast<std::string>(name), kRayKindNames, what, "visibility");
  }
  return mask;
}

}  // namespace ppm::py_convert
