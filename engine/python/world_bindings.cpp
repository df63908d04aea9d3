// Python bindings of the scene's world: a constant background, an environment image around the
// scene, and what camera rays alone see where they leave it.
#include "python/bindings.h"
#include "python/convert.h"
#include "python/ray_kinds.h"

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

void set_background(Scene& s, const py::object& c, const py::object& visible_to, int max_bounces) {
  s.set_background(color(c, "background", "color"), visibility(visible_to, "background"), max_bounces);
}

void set_environment(Scene& s, uint32_t texture, const py::object& rotation, const py::object& strength,
                     const std::string& projection, const py::object& visible_to, int max_bounces) {
  const Mat4 m = rotation.is_none() ? Mat4(1.0) : mat4(rotation, "environment", "world_to_texture");
  s.set_environment(texture, m, color(strength, "environment", "strength"),
                    choice<EnvironmentProjection>(projection,
                                                  {{"equirectangular", EnvironmentProjection::Equirectangular},
                                                   {"mirror_ball", EnvironmentProjection::MirrorBall}},
                                                  "environment", "projection"),
                    visibility(visible_to, "environment"), max_bounces);
}

void set_camera_background(Scene& s, uint32_t texture, const py::object& strength) {
  s.set_camera_background(texture, color(strength, "camera background", "strength"));
}

}  // namespace

namespace ppm::python {

void bind_world(SceneClass& c) {
  c.def("set_background", &set_background, py::arg("color"), py::arg("visibility") = py::none(),
        py::arg("max_bounces") = 1024,
        "Constant background radiance in W/(m^2 sr). visibility: the ray kinds that see it when they "
        "escape (as for add_mesh; its light on surfaces stays). max_bounces: as for add_light (the "
        "world's Max Bounces).");
  c.def("set_environment", &set_environment, py::arg("texture"), py::arg("world_to_texture") = py::none(),
        py::arg("strength") = py::make_tuple(1.0, 1.0, 1.0), py::arg("projection") = "equirectangular",
        py::arg("visibility") = py::none(), py::arg("max_bounces") = 1024,
        "The world as an image around the scene (Blender's Environment Texture): texture is an index "
        "from add_texture (linear radiance), looked up in the direction world_to_texture (a 4x4 "
        "rotation, the Mapping node's) gives, as Cycles maps 'equirectangular' or 'mirror_ball' "
        "images; times strength (RGB). Replaces set_background; visibility and max_bounces as there.");
  c.def("set_camera_background", &set_camera_background, py::arg("texture"),
        py::arg("strength") = py::make_tuple(1.0, 1.0, 1.0),
        "What camera rays see where they leave the scene instead of the background (a world whose Light "
        "Path tells camera rays apart): an equirectangular image (add_texture's index) times strength; it "
        "lights nothing. set_background and set_environment clear it.");
}

}  // namespace ppm::python
