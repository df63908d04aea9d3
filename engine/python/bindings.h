// What the binding files share: each concept's bind function (module.cpp calls the module-level
// ones, bind_scene and bind_renderer the parts of their classes) and the conversions more than
// one file uses.
#pragma once

#include "ppm/renderer.h"
#include "scene/scene.h"

#include <pybind11/pybind11.h>

#include <memory>

namespace ppm::python {

namespace py = pybind11;

using SceneClass = py::class_<Scene, std::shared_ptr<Scene>>;
using RendererClass = py::class_<Renderer>;

void bind_settings(py::module_& m);     // settings_bindings.cpp
void bind_renderer(py::module_& m);     // renderer_bindings.cpp
void bind_share(py::module_& m);        // share_bindings.cpp
void bind_scene(py::module_& m);        // scene_bindings.cpp
void bind_node_modes(py::module_& m);   // node_program_bindings.cpp
void bind_blosc(py::module_& m);        // blosc_bindings.cpp

// The parts of the Renderer class: the images it reads back (render_pass_bindings.cpp).
void bind_render_passes(RendererClass& c);
// The parts of the Scene class, one file each.
void bind_materials(SceneClass& c);     // material_bindings.cpp
void bind_textures(SceneClass& c);      // texture_bindings.cpp
void bind_grids(SceneClass& c);         // grid_bindings.cpp
void bind_meshes(SceneClass& c);        // mesh_bindings.cpp: meshes, spheres, revolves, removal
void bind_object_info(SceneClass& c);   // object_info_bindings.cpp
void bind_lights(SceneClass& c);        // light_bindings.cpp
void bind_world(SceneClass& c);         // world_bindings.cpp
void bind_camera(SceneClass& c);        // camera_bindings.cpp
void bind_scene_queries(SceneClass& c); // scene_query_bindings.cpp: intersect, run_program
void bind_media(SceneClass& c);         // medium_bindings.cpp: media; wraps add_material (after bind_materials)

// Keyword arguments or a dict to Settings, and back (settings_bindings.cpp).
Settings settings_from(const py::dict& values);
py::dict settings_dict(const Settings& s);
// What a render reports, as dicts (render_stats_bindings.cpp).
py::dict stats_dict(const RenderStats& s);
py::dict image_error_dict(const ImageError& e);

}  // namespace ppm::python
