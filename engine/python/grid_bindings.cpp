// Python bindings of Scene.add_grid and add_sparse_grid: voxel grids (a smoke domain's dense ones, an
// OpenVDB file's sparse ones) from numpy arrays, which set_object_info's `grids` hands to an object
// by slot (shading/voxel_grid.h).
#include "python/bindings.h"
#include "python/convert.h"

#include <optional>

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

py::array real_array(const py::object& values, const std::string& what, const std::string& field) {
  const py::array raw = array_or_null<py::array>(values);
  const char kind = raw ? raw.dtype().kind() : 'x';
  if (kind != 'f' && kind != 'i' && kind != 'u') fail(what, field + " must be an array of real numbers");
  return raw;
}

// The transform to index space: given (a 4x4 matrix), or None.
std::optional<Mat4> to_index_of(const py::object& to_index, const std::string& what) {
  if (to_index.is_none()) return std::nullopt;
  return mat4(to_index, what, "to_index");
}

uint32_t add_grid(Scene& s, const std::string& name, const py::object& values, const py::object& to_index,
                  bool stochastic) {
  const std::string what = "grid '" + checked_name(name, "grid") + "'";
  const py::array raw = real_array(values, what, "values");
  if (raw.ndim() != 3 && raw.ndim() != 4)
    fail(what, "values must be an array of shape (nz, ny, nx) or (nz, ny, nx, channels)");
  const int channels = raw.ndim() == 4 ? static_cast<int>(raw.shape(3)) : 1;
  check_grid_shape({raw.shape(2), raw.shape(1), raw.shape(0)}, channels, what);
  const std::optional<Mat4> m = to_index_of(to_index, what);
  const FloatArray a = array_or_null<FloatArray>(raw);
  const std::array<int, 3> size{int(raw.shape(2)), int(raw.shape(1)), int(raw.shape(0))};
  py::gil_scoped_release unlocked;
  auto grid = m ? std::make_shared<VoxelGrid>(size, channels, a.data(), *m)
                : std::make_shared<VoxelGrid>(size, channels, a.data());
  grid->set_stochastic(stochastic);
  return s.add_grid(std::move(grid));
}

std::vector<VoxelGrid::Coord> coords(const py::object& value, size_t count, const std::string& what,
                                     const std::string& field) {
  const IntArray a = array_or_null<IntArray>(value);
  if (!a || a.ndim() != 2 || a.shape(1) != 3 || size_t(a.shape(0)) != count)
    fail(what, field + " must be " + std::to_string(count) + " rows of 3 integers");
  std::vector<VoxelGrid::Coord> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = {a.at(i, 0), a.at(i, 1), a.at(i, 2)};
  return out;
}

uint32_t add_sparse_grid(Scene& s, const std::string& name, const py::object& values, const py::object& origins,
                         const py::object& to_index, const py::object& constant_origins,
                         const py::object& constant_values, bool stochastic) {
  const std::string what = "grid '" + checked_name(name, "grid") + "'";
  const py::array raw = real_array(values, what, "values");
  if (raw.ndim() != 2 && raw.ndim() != 3) fail(what, "values must be (bricks, 512) or (bricks, 512, channels)");
  const int channels = raw.ndim() == 3 ? static_cast<int>(raw.shape(2)) : 1;
  if (raw.shape(1) != VoxelGrid::kBrickVoxels) fail(what, "each brick holds 512 values (8^3, z fastest)");
  const size_t bricks = size_t(raw.shape(0));
  const std::vector<VoxelGrid::Coord> at = coords(origins, bricks, what, "origins");
  const FloatArray a = array_or_null<FloatArray>(raw);
  std::vector<VoxelGrid::Coord> constant_at;
  FloatArray constants;
  if (!constant_origins.is_none()) {
    constants = array_or_null<FloatArray>(real_array(constant_values, what, "constant_values"));
    const size_t count = constants ? size_t(constants.shape(0)) : 0;
    if (!constants || constants.size() != py::ssize_t(count * channels))
      fail(what, "constant_values must hold one value of " + std::to_string(channels) + " channels per brick");
    constant_at = coords(constant_origins, count, what, "constant_origins");
  }
  const Mat4 m = mat4(to_index, what, "to_index");
  py::gil_scoped_release unlocked;
  auto grid = std::make_shared<VoxelGrid>(channels, m, at, a.data(), constant_at,
                                          constants ? constants.data() : nullptr, what);
  grid->set_stochastic(stochastic);
  return s.add_grid(std::move(grid));
}

py::dict grid_info(const Scene& s, uint32_t index) {
  if (index >= s.grid_count()) throw py::index_error("grid index out of range");
  const auto g = s.grid(index);
  py::dict d;
  const auto lo = g->index_lo(), hi = g->index_hi();
  d["index_lo"] = py::make_tuple(lo[0], lo[1], lo[2]), d["index_hi"] = py::make_tuple(hi[0], hi[1], hi[2]);
  d["channels"] = g->channels(), d["max_value"] = g->max_value(), d["not_finite"] = g->not_finite();
  d["bricks"] = g->bricks(), d["bytes"] = g->memory_bytes();
  d["blocks"] = g->blocks(), d["regions_4096"] = g->regions_4096();
  return d;
}

}  // namespace

namespace ppm::python {

void bind_grids(SceneClass& c) {
  c.def("add_grid", &add_grid, py::arg("name"), py::arg("values"), py::arg("to_index") = py::none(),
        py::arg("stochastic") = false,
        "Adds a dense voxel grid (Blender's smoke domain grids: x fastest), shape (nz, ny, nx) or (nz, ny, nx, "
        "channels) with 1, 3 or 4 channels; `to_index`, a 4x4 matrix, maps the grid instruction's input to "
        "index space (voxel centres at integers; default: [0, 1]^3 onto the grid); `stochastic`: where paths "
        "track a medium, a lookup picks one voxel by the trilinear weights, as Cycles 5.0+ reads volume "
        "attributes (else it interpolates). Returns its index for set_object_info's `grids`. NaN and infinite "
        "values are stored as 0 (grid_info counts them).");
  c.def("add_sparse_grid", &add_sparse_grid, py::arg("name"), py::arg("values"), py::arg("origins"),
        py::arg("to_index"), py::arg("constant_origins") = py::none(), py::arg("constant_values") = py::none(),
        py::arg("stochastic") = false,
        "Adds a sparse voxel grid (an OpenVDB grid's leaves): bricks of 8^3 values (bricks, 512[, channels]), z "
        "fastest, whose first voxels lie at `origins` (bricks, 3: index coordinates, multiples of 8); "
        "constant bricks (an OpenVDB tile's) at `constant_origins` with `constant_values` (one per brick); "
        "`to_index` maps the grid instruction's input (object space) to index space; `stochastic` as "
        "add_grid's. Returns its index.");
  c.def("grid_count", &Scene::grid_count, "The number of grids added.");
  c.def("grid_info", &grid_info, py::arg("index"),
        "A grid's index box (index_lo, index_hi: its bricks' of 8^3 voxels), channels, largest colour value, "
        "NaN/Inf values stored as 0, bricks stored (empty ones are not), bytes, blocks of 128^3 voxels and regions "
        "of 4096^3 voxels holding something (OpenVDB's lower and upper nodes).");
}

}  // namespace ppm::python
