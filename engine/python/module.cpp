// The `ppm_core` Python module: progressive photon mapping for Blender.
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_scene(py::module_& m);
void bind_renderer(py::module_& m);
void bind_share(py::module_& m);
namespace ppm::py_convert {
py::dict node_modes();
}

PYBIND11_MODULE(ppm_core, m) {
  m.doc() = "Progressive photon mapping core: Scene (builders, intersect), Settings, Renderer.";
  bind_scene(m);
  bind_renderer(m);
  bind_share(m);
  m.def("node_modes", &ppm::py_convert::node_modes,
        "Each node program operation's modes by name, in the order the core numbers them.");
}
