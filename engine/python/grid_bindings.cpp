// Python binding of Scene.add_grid: a voxel grid (a smoke domain's) from a numpy array, which
// set_object_info's `grids` hands to an object by slot (shading/voxel_grid.h).
#include "python/bindings.h"
#include "python/convert.h"

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

uint32_t add_grid(Scene& s, const std::string& name, const py::object& values) {
  using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
  const std::string what = "grid '" + checked_name(name, "grid") + "'";
  const py::array raw = array_or_null<py::array>(values);
  if (!raw || (raw.ndim() != 3 && raw.ndim() != 4))
    fail(what, "values must be an array of shape (nz, ny, nx) or (nz, ny, nx, channels)");
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') fail(what, "values must be real numbers");
  const int channels = raw.ndim() == 4 ? static_cast<int>(raw.shape(3)) : 1;
  check_grid_shape({raw.shape(2), raw.shape(1), raw.shape(0)}, channels, what);
  const FloatArray a = array_or_null<FloatArray>(raw);
  if (!a) fail(what, "values must be an array of numbers");
  const std::array<int, 3> size{int(raw.shape(2)), int(raw.shape(1)), int(raw.shape(0))};
  py::gil_scoped_release unlocked;
  return s.add_grid(std::make_shared<const VoxelGrid>(size, channels, a.data()));
}

py::dict grid_info(const Scene& s, uint32_t index) {
  if (index >= s.grid_count()) throw py::index_error("grid index out of range");
  const auto g = s.grid(index);
  py::dict d;
  const auto lo = g->index_lo(), hi = g->index_hi();
  d["index_lo"] = py::make_tuple(lo[0], lo[1], lo[2]), d["index_hi"] = py::make_tuple(hi[0], hi[1], hi[2]);
  d["channels"] = g->channels(), d["max_value"] = g->max_value(), d["not_finite"] = g->not_finite();
  d["bricks"] = g->bricks(), d["bytes"] = g->memory_bytes();
  return d;
}

}  // namespace

namespace ppm::python {

void bind_grids(SceneClass& c) {
  c.def("add_grid", &add_grid, py::arg("name"), py::arg("values"),
        "Adds a dense voxel grid over an object's texture space (Blender's smoke domain grids: x fastest), "
        "shape (nz, ny, nx) or (nz, ny, nx, channels) with 1, 3 or 4 channels; returns its index for "
        "set_object_info's `grids`. NaN and infinite values are stored as 0 (grid_info counts them).");
  c.def("grid_info", &grid_info, py::arg("index"),
        "A grid's index box (index_lo, index_hi: its bricks' of 8^3 voxels), channels, largest colour value, "
        "NaN/Inf values stored as 0, bricks stored (empty ones are not) and bytes.");
}

}  // namespace ppm::python
