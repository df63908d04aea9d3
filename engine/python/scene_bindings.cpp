// Python bindings of ppm::Scene: the class, how it builds and keeps its BVH, and its counts. Its
// builders and queries are bound one concept a file (bindings.h lists them).
#include "python/bindings.h"
#include "python/convert.h"

#include <string>

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

std::string geometry_layout(const Scene& s) {
  const GeometryLayout l = s.geometry().layout();
  return std::string(l == GeometryLayout::Auto ? "auto" : l == GeometryLayout::Copies ? "copies" : "compact");
}

void set_geometry_layout(Scene& s, const std::string& layout) {
  s.set_geometry_layout(choice<GeometryLayout>(
      layout, {{"auto", GeometryLayout::Auto}, {"copies", GeometryLayout::Copies}, {"compact", GeometryLayout::Compact}},
      "scene", "geometry_layout"));
}

// How the scene builds its BVH and keeps its triangles.
void bind_build(python::SceneClass& c) {
  c.def_property_readonly("subtrees_built", [](const Scene& s) { return s.geometry().subtrees_built(); },
                          "How many objects' BVH subtrees the last build() of a dynamic scene built; the "
                          "others were kept (objects added or given other primitives are built, moved ones "
                          "refitted).");
  c.def_property("dynamic", [](const Scene& s) { return s.geometry().dynamic(); }, &Scene::set_dynamic,
                 "Build the BVH object by object (False by default), so that objects can be added, moved, "
                 "reshaped and removed in a built scene at the cost of their own subtrees (the viewport); a "
                 "whole-scene BVH traces faster where objects overlap.");
  c.def_property("geometry_layout", &geometry_layout, &set_geometry_layout,
                 "How the built scene keeps its triangles for ray tests: 'copies' (each triangle's corners copied beside "
                 "the BVH, 96 bytes a triangle more, the fastest), 'compact' (only its mesh's shared vertices) or 'auto' "
                 "(copies up to 4,000,000 triangles; the default). The hits are the same, bit for bit.");
  c.def_property_readonly("triangles_copied", [](const Scene& s) { return s.geometry().triangles_copied(); },
                          "Whether the built scene keeps copies of its triangles (geometry_layout).");
  c.def("build", &Scene::build, "Builds the BVH (done automatically by Renderer and intersect).");
  c.def_property_readonly("primitive_count", [](Scene& s) { s.build(); return s.geometry().primitive_count(); });
  c.def_property_readonly("light_count", [](Scene& s) { s.build(); return s.lights().size(); });
}

}  // namespace

namespace ppm::python {

void bind_scene(py::module_& m) {
  SceneClass c(m, "Scene", "A scene for the PPM core. World space: metres, Z up.");
  c.def(py::init<>());
  bind_materials(c);
  bind_object_info(c);
  bind_textures(c);
  bind_grids(c);
  bind_meshes(c);
  bind_build(c);
  bind_lights(c);
  bind_camera(c);
  bind_world(c);
  bind_scene_queries(c);
  bind_media(c);
}

}  // namespace ppm::python
