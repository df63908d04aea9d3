// Python bindings of the scene's geometry: triangle meshes (added, or replacing an object's),
// spheres and surfaces of revolution, and the removal of an object's primitives.
#include "python/bindings.h"
#include "python/convert.h"
#include "python/ray_kinds.h"

#include <cmath>
#include <vector>

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

// Integers in [0, 2^32) from float (and object) arrays: only if every entry is a whole number, so
// that 0.5 or NaN is an error rather than silently truncated to a valid index.
std::vector<uint32_t> whole_numbers(const py::array& raw, const std::string& what, const std::string& field) {
  const DoubleArray a = array_or_null<DoubleArray>(raw);
  if (!a) fail(what, field + " must be an array of integers");
  std::vector<uint32_t> out(raw.size());
  const double* p = a.data();
  for (size_t i = 0; i < out.size(); ++i) {
    if (!(p[i] == std::floor(p[i]))) fail(what, field + " entry " + std::to_string(i) + " is not an integer");
    if (p[i] < 0.0 || p[i] > 4294967295.0) fail(what, field + " entry " + std::to_string(i) + " is out of range");
    out[i] = static_cast<uint32_t>(p[i]);
  }
  return out;
}

// Integers in [0, 2^32): integer and boolean arrays as they are, float and object arrays as
// whole_numbers.
std::vector<uint32_t> index_list(const py::handle& obj, const std::string& what, const std::string& field) {
  using IntArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
  const py::array raw = py::array::ensure(obj);
  if (!raw) fail(what, field + " must be an array of integers");
  const char kind = raw.dtype().kind();
  if (kind == 'f' || kind == 'O') return whole_numbers(raw, what, field);
  if (kind != 'i' && kind != 'u' && kind != 'b')
    fail(what, field + std::string(" must be an array of integers, not dtype kind '") + kind + "'");
  const IntArray a = array_or_null<IntArray>(raw);
  if (!a) fail(what, field + " must be an array of integers");
  std::vector<uint32_t> out(raw.size());
  const int64_t* p = a.data();
  const bool unsigned64 = kind == 'u' && raw.dtype().itemsize() == 8;  // >= 2^63 wrapped to negative
  for (size_t i = 0; i < out.size(); ++i) {
    if (p[i] < 0 || p[i] > 0xffffffffll)
      fail(what, field + " entry " + std::to_string(i) + " is out of range" +
                     (unsigned64 && p[i] < 0 ? " (above 2^63)" : ""));
    out[i] = static_cast<uint32_t>(p[i]);
  }
  return out;
}

// Rows of `columns` numbers per vertex (V, columns) or per corner (T, 3, columns), as (N, columns).
DoubleArray corner_rows(const py::object& values, py::ssize_t columns) {
  DoubleArray a = DoubleArray::ensure(values);
  if (a && a.ndim() == 3 && a.shape(1) == 3 && a.shape(2) == columns) a = a.reshape({a.shape(0) * 3, columns});
  return a;
}

// Four numbers per vertex or per corner (tangents, colours).
template <class Vec4>
std::vector<Vec4> rows_of_four(const py::object& values, const std::string& what, const std::string& field) {
  const DoubleArray a = corner_rows(values, 4);
  if (!a || a.ndim() != 2 || a.shape(1) != 4)
    fail(what, field + " must have one row per vertex (V, 4) or per corner (T, 3, 4)");
  std::vector<Vec4> out;
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < r.shape(0); ++i) out.emplace_back(r(i, 0), r(i, 1), r(i, 2), r(i, 3));
  return out;
}

// Normals and UVs per vertex or per corner.
void shading_rows(MeshInput& m, const py::object& normals, const py::object& uvs, const std::string& what) {
  const size_t nt = m.triangles.size() / 3;
  if (!normals.is_none()) {
    m.normals = vec3_list(corner_rows(normals, 3), what, "normals");
    if (m.normals.size() != m.positions.size() && m.normals.size() != 3 * nt)
      fail(what, "normals must have one row per vertex (V, 3) or per corner (T, 3, 3)");
  }
  if (!uvs.is_none()) {
    m.uvs = vec2_list(corner_rows(uvs, 2), what, "uvs");
    if (m.uvs.size() != m.positions.size() && m.uvs.size() != 3 * nt)
      fail(what, "uvs must have one row per vertex (V, 2) or per corner (T, 3, 2)");
  }
}

MeshInput mesh_input(const std::string& name, const py::object& positions, const py::object& triangles,
                     const py::object& normals, const py::object& uvs, const py::object& materials,
                     uint32_t object_id, const py::object& visible_to, bool holdout, const py::object& tangents,
                     const py::object& colors) {
  const std::string what = "mesh '" + checked_name(name, "mesh") + "'";
  MeshInput m;
  m.name = name;
  m.object_id = object_id;
  m.visibility = visibility(visible_to, what) | (holdout ? kHoldoutFlag : 0);
  m.positions = vec3_list(positions, what, "positions");
  const py::array t = py::array::ensure(triangles);
  if (!t || t.ndim() != 2 || t.shape(1) != 3) fail(what, "triangles must be an integer array of shape (T, 3)");
  m.triangles = index_list(t, what, "triangles");
  shading_rows(m, normals, uvs, what);
  if (!tangents.is_none()) m.tangents = rows_of_four<decltype(m.tangents)::value_type>(tangents, what, "tangents");
  if (!colors.is_none()) m.colors = rows_of_four<decltype(m.colors)::value_type>(colors, what, "colors");
  m.materials = index_list(materials, what, "materials");
  return m;
}

// add_mesh and replace_mesh: the same arguments into a MeshInput for the scene's method.
template <void (Scene::*method)(const MeshInput&)>
void mesh_call(Scene& s, const std::string& name, const py::object& positions, const py::object& triangles,
               const py::object& normals, const py::object& uvs, const py::object& materials, uint32_t object_id,
               const py::object& visible_to, bool holdout, const py::object& tangents, const py::object& colors) {
  (s.*method)(mesh_input(name, positions, triangles, normals, uvs, materials, object_id, visible_to, holdout,
                         tangents, colors));
}

void add_sphere(Scene& s, const std::string& name, const py::object& center, double radius, uint32_t material,
                uint32_t object_id, const py::object& visible_to, bool holdout) {
  const std::string what = "sphere '" + checked_name(name, "sphere") + "'";
  s.add_sphere(name, vec3(center, what, "center"), radius, material, object_id,
               visibility(visible_to, what) | (holdout ? kHoldoutFlag : 0));
}

void add_bezier_revolve(Scene& s, const std::string& name, const py::object& points, const std::string& kind,
                        const py::object& matrix, uint32_t material, uint32_t object_id, const py::object& visible_to,
                        bool holdout) {
  const std::string what = "bezier revolve '" + checked_name(name, "bezier revolve") + "'";
  const bool chain = choice<bool>(kind, {{"single", false}, {"chain", true}}, what, "kind");
  const Mat4 m = matrix.is_none() ? Mat4(1.0) : mat4(matrix, what, "matrix");
  s.add_bezier_revolve(name, vec2_list(points, what, "points"), chain, m, material, object_id,
                       visibility(visible_to, what) | (holdout ? kHoldoutFlag : 0));
}

}  // namespace

namespace ppm::python {

void bind_meshes(SceneClass& c) {
  c.def("add_mesh", &mesh_call<&Scene::add_mesh>, py::arg("name"), py::arg("positions"), py::arg("triangles"),
        py::arg("normals") = py::none(), py::arg("uvs") = py::none(), py::arg("materials") = 0,
        py::arg("object_id") = 0, py::arg("visibility") = py::none(), py::arg("holdout") = false,
        py::arg("tangents") = py::none(), py::arg("colors") = py::none(),
        "Adds a world-space triangle mesh. normals/uvs/tangents per vertex or per corner (T, 3, k); "
        "tangents (k = 4): the UV map's tangent and, in the 4th column, the bitangent's sign (for "
        "tangent-space normal maps); colors (k = 4): the attribute node programs read (Attribute and Color "
        "Attribute nodes). materials: one index or one per triangle. visibility: the ray kinds that see it "
        "('camera', 'diffuse', 'glossy', 'transmission', 'shadow'; None: all), as Cycles' ray visibility. "
        "holdout: a hole in the image (alpha 0) where camera rays reach it; other rays see it as it is.");
  c.def("replace_mesh", &mesh_call<&Scene::replace_mesh>, py::arg("name"), py::arg("positions"),
        py::arg("triangles"), py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
        py::arg("materials") = 0, py::arg("object_id") = 0, py::arg("visibility") = py::none(),
        py::arg("holdout") = false, py::arg("tangents") = py::none(), py::arg("colors") = py::none(),
        "Object `object_id`'s triangles (it has no other primitives) become this mesh's, arguments as for "
        "add_mesh: moved, or reshaped with any number of triangles and attributes, in the place of the "
        "object's first triangle. In a built dynamic scene, a mesh moved or reshaped with as many triangles "
        "and the same attributes refits the object's BVH subtree at build(); any other builds that subtree "
        "again and keeps the other objects'. Elsewhere the BVH is built afresh. ValueError where it cannot, "
        "the scene unchanged (the caller then builds a new Scene).");
  c.def("remove_object", &Scene::remove_object, py::arg("object_id"),
        "Removes every primitive of object `object_id` (meshes, spheres, revolves) and returns how many "
        "there were (0: none, the scene unchanged). In a built dynamic scene build() then drops the "
        "object's BVH subtree and keeps the other objects'.");
  c.def("add_sphere", &add_sphere, py::arg("name"), py::arg("center"), py::arg("radius"), py::arg("material"),
        py::arg("object_id") = 0, py::arg("visibility") = py::none(), py::arg("holdout") = false,
        "Adds a sphere; visibility and holdout as for add_mesh.");
  c.def("add_bezier_revolve", &add_bezier_revolve, py::arg("name"), py::arg("points"), py::arg("kind") = "single",
        py::arg("matrix") = py::none(), py::arg("material") = 0, py::arg("object_id") = 0,
        py::arg("visibility") = py::none(), py::arg("holdout") = false,
        "Adds a surface of revolution: profile points (radius, height) revolved about local Z. "
        "kind 'single' (one Bezier curve, degree 1-8) or 'chain' (cubic segments, 3k+1 points); "
        "visibility and holdout as for add_mesh.");
}

}  // namespace ppm::python
