// Python bindings of what a scene answers outside a render: rays cast in a batch (scene/ray_batch.h,
// the GIL released), a node program run at given points (scene/program_points.h) and the media a
// point is in.
#include "python/bindings.h"
#include "python/convert.h"
#include "python/node_program_bindings.h"
#include "python/ray_kinds.h"
#include "scene/program_points.h"
#include "scene/ray_batch.h"

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

py::dict intersect(Scene& s, const py::object& origins, const py::object& directions, int threads,
                   const py::object& ray_kind) {
  const uint8_t kind = ray_kind.is_none() ? kAllRayKinds
                                          : choice<uint8_t>(py::cast<std::string>(py::str(ray_kind)), kRayKindNames,
                                                            "intersect", "ray_kind");
  const DoubleArray o = matrix(origins, 3, "intersect", "origins");
  const DoubleArray d = matrix(directions, 3, "intersect", "directions");
  if (o.shape(0) != d.shape(0)) fail("intersect", "origins and directions must have the same length");
  if (threads < 0) fail("intersect", "threads must be >= 0 (0: all hardware threads)");
  const size_t n = o.shape(0);
  check_ray_arrays(o.data(), d.data(), n);
  s.build();
  py::array_t<double> t(n);
  py::array_t<double> normal({n, size_t(3)});
  py::array_t<int64_t> prim(n), object(n), material(n);
  const HitArrays hits{t.mutable_data(), normal.mutable_data(), prim.mutable_data(), object.mutable_data(),
                       material.mutable_data()};
  {
    py::gil_scoped_release release;
    intersect_arrays(s, o.data(), d.data(), n, kind, threads, hits);
  }
  py::dict out;
  out["t"] = t;
  out["normal"] = normal;
  out["primitive"] = prim;
  out["object"] = object;
  out["material"] = material;
  return out;
}

// The points' attributes: each given (one row per position) or the default everywhere.
ProgramPoints program_points(const py::object& position, const py::object& normal, const py::object& incoming,
                             const py::object& uv, const py::object& tangent, const std::string& what) {
  ProgramPoints points;
  points.positions = vec3_list(position, what, "position");
  const size_t n = points.positions.size();
  auto optional3 = [&](const py::object& v, const char* field, Vec3 fallback) {
    std::vector<Vec3> out = v.is_none() ? std::vector<Vec3>(n, fallback) : vec3_list(v, what, field);
    if (out.size() != n) fail(what, std::string(field) + " must have one row per position");
    return out;
  };
  points.normals = optional3(normal, "normal", Vec3(0.0, 0.0, 1.0));
  points.incomings = optional3(incoming, "incoming", Vec3(0.0, 0.0, 1.0));
  points.uvs = uv.is_none() ? std::vector<Vec2>(n, Vec2(0.0)) : vec2_list(uv, what, "uv");
  if (points.uvs.size() != n) fail(what, "uv must have one row per position");
  if (!tangent.is_none()) {
    const DoubleArray t = matrix(tangent, 4, what, "tangent");
    if (static_cast<size_t>(t.shape(0)) != n) fail(what, "tangent must have one row per position");
    points.tangents.assign(t.data(), t.data() + 4 * n);
  }
  return points;
}

// Runs a node program at n points (tests and the add-on's constant folding): (n, outputs, 3).
py::array_t<float> run_program(const Scene& s, const py::object& program, const py::object& position,
                               const py::object& normal, const py::object& incoming, const py::object& uv,
                               const py::object& tangent, uint32_t object, double footprint,
                               const std::string& ray) {
  const std::string what = "run_program";
  const uint8_t kind = choice<uint8_t>(ray, {{"camera", kCameraRay}, {"diffuse", kDiffuseRay}, {"glossy", kGlossyRay},
                                             {"transmission", kTransmissionRay}, {"shadow", kShadowRay}, {"emission", 0}},
                                       what, "ray");
  const NodeProgram p = program_from(program, what);
  p.validate(s.textures().size(), what);
  const ProgramPoints points = program_points(position, normal, incoming, uv, tangent, what);
  py::array_t<float> out({points.positions.size(), p.outputs.size(), size_t(3)});
  run_program_at(s, p, points, object, footprint, kind, out.mutable_data());
  return out;
}

}  // namespace

namespace ppm::python {

void bind_scene_queries(SceneClass& c) {
  c.def("intersect", &intersect, py::arg("origins"), py::arg("directions"), py::arg("threads") = 0,
        py::arg("ray_kind") = py::none(),
        "Casts rays: returns dict(t (inf on miss), normal (geometric), primitive, object, material (-1 on "
        "miss)). "
        "threads: 0 uses all hardware threads. ray_kind: 'camera', 'diffuse', ... to pass through "
        "what that kind of ray does not see (None: hit everything visible to any ray).");
  c.def("run_program", &run_program, py::arg("program"), py::arg("position"), py::arg("normal") = py::none(),
        py::arg("incoming") = py::none(), py::arg("uv") = py::none(), py::arg("tangent") = py::none(),
        py::arg("object") = 0, py::arg("footprint") = 0.0, py::arg("ray") = "camera",
        "Runs a node program (add_material's `program`) at points (their normals, the direction towards "
        "the viewer, UVs, and UV tangents with the bitangent sign, (n, 4); footprint: the world size of a "
        "pixel there, as a camera ray sees it; ray: the kind of ray that arrived, as the Light Path node "
        "reads it: camera, diffuse, glossy, transmission, shadow or emission): float32 (n, outputs, 3).");
  c.def(
      "media_at",
      [](Scene& s, const py::object& point) {
        const Vec3 p = vec3(point, "media_at", "point");
        s.build();
        const MediumStack stack = s.media_at(p);
        py::list names;
        for (int k = 0; k < stack.count; ++k) names.append(s.medium(static_cast<uint32_t>(stack.ids[k])).name);
        return names;
      },
      py::arg("point"),
      "The names of the mesh media that hold `point`, outermost first (where a camera or light there "
      "starts its paths; the world's medium is not listed).");
}

}  // namespace ppm::python
