// The `ppm_core` Python module: progressive photon mapping for Blender.
#include "base/memory_budget.h"
#include "python/bindings.h"

#include <pybind11/pybind11.h>

namespace py = pybind11;

PYBIND11_MODULE(ppm_core, m) {
  m.doc() = "Progressive photon mapping core: Scene (builders, intersect), Settings, Renderer.";
  // A render the machine has no memory for (memory_budget.h): MemoryError, with its message.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ppm::MemoryShortage& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    }
  });
  ppm::python::bind_scene(m);
  ppm::python::bind_settings(m);
  ppm::python::bind_renderer(m);
  ppm::python::bind_share(m);
  ppm::python::bind_node_modes(m);
  ppm::python::bind_blosc(m);
}
