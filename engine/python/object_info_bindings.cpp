// Python binding of Scene.set_object_info: what node programs know of an object (its matrix and
// texture space, scene/object_info.h; Object Info's Random, Pass Index and Color; its attributes and
// voxel grids).
#include "python/bindings.h"
#include "python/convert.h"
#include "scene/object_info.h"

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

glm::vec4 rgba(const double* p, const std::string& what, const std::string& field) {
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(p[k])) fail(what, field + " must be finite");
  return glm::vec4(float(p[0]), float(p[1]), float(p[2]), float(p[3]));
}

void set_object_info(Scene& s, uint32_t object, const py::object& object_to_world,
                     const py::object& texspace_location, const py::object& texspace_size, double random,
                     double pass_index, const py::object& color, const py::object& attributes,
                     const py::object& grids, double volume_density) {
  const std::string what = "object " + std::to_string(object);
  const Mat4 to_world = mat4(object_to_world, what, "matrix");
  const Vec3 location = vec3(texspace_location, what, "texspace_location");
  ObjectInfo info = object_info(to_world, location, vec3(texspace_size, what, "texspace_size"));
  info.random = static_cast<float>(random);
  info.pass_index = static_cast<float>(pass_index);
  const DoubleArray c = array_or_null<DoubleArray>(color);
  if (!c || c.size() != 4) fail(what, "color must be 4 numbers (RGBA)");
  info.color = rgba(c.data(), what, "color");
  if (!attributes.is_none()) {
    const DoubleArray a = matrix(attributes, 4, what, "attributes");
    for (py::ssize_t i = 0; i < a.shape(0); ++i) info.attributes.push_back(rgba(a.data() + 4 * i, what, "attributes"));
  }
  if (!(volume_density >= 0.0 && volume_density <= 1e30)) fail(what, "volume_density must be in [0, 1e30]");
  info.volume_density = static_cast<float>(volume_density);
  if (!grids.is_none()) {
    for (const py::handle g : py::cast<py::sequence>(grids)) {
      const long long index = g.is_none() ? -1 : py::cast<long long>(g);
      if (index >= static_cast<long long>(s.grid_count())) fail(what, "grids names a grid that does not exist");
      info.grids.push_back(index < 0 ? nullptr : s.grid(static_cast<uint32_t>(index)));
    }
  }
  s.set_object_info(object, info);
}

}  // namespace

namespace ppm::python {

void bind_object_info(SceneClass& c) {
  c.def("set_object_info", &set_object_info, py::arg("object"), py::arg("matrix"),
        py::arg("texspace_location") = py::make_tuple(0.0, 0.0, 0.0),
        py::arg("texspace_size") = py::make_tuple(1.0, 1.0, 1.0), py::arg("random") = 0.0,
        py::arg("pass_index") = 0.0, py::arg("color") = py::make_tuple(1.0, 1.0, 1.0, 1.0),
        py::arg("attributes") = py::none(), py::arg("grids") = py::none(), py::arg("volume_density") = 1.0,
        "What node programs know of object id `object` (add_mesh's object_id): its object-to-world matrix "
        "(Texture Coordinate's Object), its texture space (Blender's texspace_location and _size: Generated), "
        "Object Info's Random, Pass Index and Color (RGBA), and `attributes`: (n, 4) RGBA values the "
        "program's object_attribute coordinates read by slot (the instruction's data); finite numbers only; "
        "`grids`: add_grid indices by slot (None or -1: none), which the program's grid instructions read; "
        "`volume_density`: what its media that vary are multiplied by (Cycles' Volume objects follow their "
        "scale so).");
}

}  // namespace ppm::python
