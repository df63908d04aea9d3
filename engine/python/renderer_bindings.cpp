// Python bindings of the renderer: making one, run() (the GIL released; the progress callback
// and Ctrl-C checks take it back briefly), cancel, share, stats and settings. The images it reads
// back are render_pass_bindings.cpp's.
#include "python/bindings.h"

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <functional>

namespace py = pybind11;
using namespace ppm;

namespace {

// Settings from a Settings, a dict or None, with keyword arguments over them.
Settings renderer_settings(const py::object& settings, const py::kwargs& overrides) {
  py::dict values;
  if (py::isinstance<Settings>(settings)) values = python::settings_dict(settings.cast<Settings>());
  else if (py::isinstance<py::dict>(settings)) values = settings.cast<py::dict>();
  else if (!settings.is_none()) throw std::invalid_argument("Renderer: settings must be a Settings, a dict or None");
  for (const auto& [k, v] : overrides) values[k] = v;
  return python::settings_from(values);
}

// What the progress callback returned: None or a truth value (Python's or numpy's) says go on or cancel.
bool go_on(const py::object& result) {
  if (result.is_none()) return true;
  const bool numpy_flag = py::hasattr(result, "dtype") && py::hasattr(result, "ndim") &&
                          result.attr("ndim").cast<int>() == 0 &&
                          std::string("biu").find(py::str(result.attr("dtype").attr("kind")).cast<std::string>()) !=
                              std::string::npos;
  if (!py::isinstance<py::bool_>(result) && !py::isinstance<py::int_>(result) && !numpy_flag)
    throw std::invalid_argument("run: the callback must return None, True (go on) or False (cancel), not " +
                                std::string(py::str(py::type::of(result).attr("__name__"))));
  return PyObject_IsTrue(result.ptr()) == 1;
}

// The poll run() calls from its threads: the GIL taken back to check Ctrl-C and call `callback`.
std::function<bool(const Progress&)> progress_poll(const py::object& callback) {
  return [&callback](const Progress& p) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C cancels
    if (callback.is_none()) return true;
    py::dict info;
    info["passes"] = p.passes;
    info["photons_emitted"] = p.photons_emitted;
    info["seconds"] = p.seconds;
    info["pass_done"] = p.pass_done;
    return go_on(callback(info));
  };
}

uint64_t run(Renderer& r, uint64_t passes, double seconds, const py::object& callback, double pause_after) {
  const std::function<bool(const Progress&)> poll = progress_poll(callback);
  py::gil_scoped_release release;
  return r.run(passes, seconds, poll, pause_after);
}

}  // namespace

namespace ppm::python {

void bind_renderer(py::module_& m) {
  RendererClass c(m, "Renderer", "Progressive photon mapping of a Scene.");
  c.def(py::init([](std::shared_ptr<Scene> scene, const py::object& settings, const py::kwargs& overrides) {
          if (!scene) throw std::invalid_argument("Renderer: scene is None");
          return make_renderer(scene, renderer_settings(settings, overrides));
        }),
        py::arg("scene"), py::arg("settings") = py::none());
  c.def("run", &run, py::arg("passes") = 0, py::arg("seconds") = 0.0, py::arg("callback") = py::none(),
        py::arg("pause_after") = 0.0,
        "Runs passes until `passes` are done or `seconds` have passed (0 = no limit for either). "
        "callback(dict(passes, photons_emitted, seconds, pass_done)) is called often (pass_done: the share of "
        "the pass in progress already in the image); returning False cancels. pause_after > 0: a "
        "stochastic pass still running that many seconds after the start returns at the end of its band "
        "of rows, its finished bands in the image (stats()['pass_done']); the next run() continues it. "
        "Returns the number of passes completed.");
  c.def("share", &Renderer::share, py::call_guard<py::gil_scoped_release>(),
        "With radius_schedule='global': the passes so far as a Share, to merge with other renderers' "
        "(merge_shares), e.g. on other machines with first_pass set to the passes before theirs.");
  c.def("cancel", &Renderer::cancel, "Stops a run() in progress (callable from another thread).");
  c.def("stats", [](const Renderer& r) { return stats_dict(r.stats()); });
  c.def_property_readonly("settings", [](const Renderer& r) { return settings_dict(r.settings()); });
  bind_render_passes(c);
}

}  // namespace ppm::python
