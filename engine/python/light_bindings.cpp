// Python bindings of the scene's lights: a LightSpec from Cycles' light settings (scene/light.h
// makes the light), and their removal.
#include "python/bindings.h"
#include "python/convert.h"
#include "python/ray_kinds.h"

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

LightKind light_kind(const std::string& kind, const std::string& what) {
  return choice<LightKind>(kind,
                           {{"point", LightKind::Point},
                            {"sphere", LightKind::Sphere},
                            {"spot", LightKind::Spot},
                            {"rectangle", LightKind::Rectangle},
                            {"disk", LightKind::Disk},
                            {"sun", LightKind::Sun}},
                           what, "kind");
}

// Where the light is: a matrix, or a position and a direction; an area light's size.
void placement(LightSpec& spec, const py::object& position, const py::object& direction, const py::object& matrix,
               const py::object& size, const std::string& what) {
  spec.has_matrix = !matrix.is_none();
  if (spec.has_matrix) spec.matrix = mat4(matrix, what, "matrix");
  if (!position.is_none()) spec.position = vec3(position, what, "position");
  if (!direction.is_none()) spec.direction = vec3(direction, what, "direction");
  if (!size.is_none()) {
    const DoubleArray a = numbers_or_null(size);
    if (!a || (a.size() != 1 && a.size() != 2)) fail(what, "size must be one number or (size_x, size_y)");
    spec.size_x = a.data()[0];
    spec.size_y = a.data()[a.size() - 1];
  }
}

void add_light(Scene& s, const std::string& kind, const std::string& name, const py::object& power,
               const py::object& color_obj, const py::object& position, const py::object& direction,
               const py::object& matrix, const py::object& size, double radius, double spot_angle,
               double spot_blend, double angle, bool spot_cosine_falloff, bool soft_falloff,
               const py::object& visible_to, bool cast_shadow, double spread, int max_bounces) {
  const std::string what = "light '" + checked_name(name, "light") + "'";
  LightSpec spec;
  spec.name = name;
  spec.kind = light_kind(kind, what);
  spec.visibility = visibility(visible_to, what);
  spec.power = color(power, what, "power") * color(color_obj, what, "color");
  placement(spec, position, direction, matrix, size, what);
  spec.radius = radius;
  spec.spot_angle = spot_angle;
  spec.spot_blend = spot_blend;
  spec.angle = angle;
  spec.spot_cosine_falloff = spot_cosine_falloff;
  spec.soft_falloff = soft_falloff;
  spec.cast_shadow = cast_shadow;
  spec.spread = spread;
  spec.max_bounces = max_bounces;
  s.add_light(make_light(spec));
}

}  // namespace

namespace ppm::python {

void bind_lights(SceneClass& c) {
  c.def("add_light", &add_light, py::arg("kind"), py::arg("name") = "light", py::arg("power") = 100.0,
        py::arg("color") = py::make_tuple(1.0, 1.0, 1.0), py::arg("position") = py::none(),
        py::arg("direction") = py::none(), py::arg("matrix") = py::none(), py::arg("size") = py::none(),
        py::arg("radius") = 0.0, py::arg("spot_angle") = kPi / 4.0, py::arg("spot_blend") = 0.15,
        py::arg("angle") = 0.0, py::arg("spot_cosine_falloff") = false, py::arg("soft_falloff") = false,
        py::arg("visibility") = py::none(), py::arg("cast_shadow") = true, py::arg("spread") = kPi,
        py::arg("max_bounces") = 1024,
        "Adds a light in Cycles units. point/sphere/spot: power in W (intensity P/(4 pi)); rectangle/disk: "
        "emitted flux in W; sun: irradiance in W/m^2. Orientation from `matrix` (Blender's: emits along "
        "local -Z) or from position/direction. radius: a point's or spot's sphere. spot_cosine_falloff: "
        "Cycles 3.x's extra cos factor on spots; soft_falloff: Cycles' sphere-light falloff "
        "I cos/(d^2 + r^2) for direct light. spread: a rectangle's or disk's spread angle in radians, as "
        "Cycles' (pi: Lambertian). visibility: the ray kinds that see a light with a surface when they "
        "reach it (as for add_mesh; Blender lights leave out 'camera'); cast_shadow: False lights through "
        "everything in the way. max_bounces: Cycles' per-light Max Bounces, the longest path (in "
        "scatterings) the light reaches; 1024 is no limit.");
  c.def("remove_lights", &Scene::remove_lights,
        "Removes every light add_light added; the world and emissive surfaces stay. A built scene keeps "
        "its BVH: replacing the lights of a large scene costs the lights alone.");
}

}  // namespace ppm::python
