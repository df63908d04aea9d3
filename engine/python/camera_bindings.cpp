// Python bindings of the scene's camera: set from Blender's camera settings, and its primary rays.
#include "python/bindings.h"
#include "python/convert.h"

#include <pybind11/stl.h>

#include <array>

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

void set_camera(Scene& s, const py::object& matrix, int width, int height, const std::string& projection,
                double fov, double ortho_scale, const std::string& sensor_fit, double shift_x, double shift_y,
                double clip_start, double clip_end, double focus_distance, double aperture_radius,
                double focal_length, const py::object& frame) {
  Camera c;
  if (!frame.is_none()) {
    const auto f = frame.cast<std::array<int, 4>>();
    c.frame_x = f[0];
    c.frame_y = f[1];
    c.frame_width = f[2];
    c.frame_height = f[3];
  }
  c.camera_to_world = mat4(matrix, "camera", "matrix");
  c.width = width;
  c.height = height;
  c.projection = choice<Projection>(
      projection, {{"perspective", Projection::Perspective}, {"orthographic", Projection::Orthographic}}, "camera",
      "projection");
  c.sensor_fit = choice<SensorFit>(
      sensor_fit, {{"auto", SensorFit::Auto}, {"horizontal", SensorFit::Horizontal}, {"vertical", SensorFit::Vertical}},
      "camera", "sensor_fit");
  c.fov = fov;
  c.ortho_scale = ortho_scale;
  c.shift_x = shift_x;
  c.shift_y = shift_y;
  c.clip_start = clip_start;
  c.clip_end = clip_end;
  c.focus_distance = focus_distance;
  c.aperture_radius = aperture_radius;
  c.focal_length = focal_length;
  s.set_camera(c);
}

// The camera's primary ray through every pixel centre, bottom row first: (origins, directions),
// each (width * height, 3).
py::tuple camera_rays(const Scene& s) {
  if (!s.has_camera()) fail("camera_rays", "the scene has no camera (call set_camera)");
  const Camera& cam = s.camera();
  const size_t n = static_cast<size_t>(cam.width) * cam.height;
  py::array_t<double> origins({n, size_t(3)}), directions({n, size_t(3)});
  pixel_centre_rays(cam, origins.mutable_data(), directions.mutable_data());
  return py::make_tuple(origins, directions);
}

}  // namespace

namespace ppm::python {

void bind_camera(SceneClass& c) {
  c.def("set_camera", &set_camera, py::arg("matrix"), py::arg("width"), py::arg("height"),
        py::arg("projection") = "perspective", py::arg("fov") = 0.8575560591178853, py::arg("ortho_scale") = 7.0,
        py::arg("sensor_fit") = "auto", py::arg("shift_x") = 0.0, py::arg("shift_y") = 0.0,
        py::arg("clip_start") = 1e-3, py::arg("clip_end") = kInf, py::arg("focus_distance") = 10.0,
        py::arg("aperture_radius") = 0.0, py::arg("focal_length") = 0.0, py::arg("frame") = py::none(),
        "Sets the camera: camera-to-world matrix (looks down local -Z), image size, field of view "
        "in radians across the fitted side. Depth of field: focus_distance and aperture_radius in "
        "metres, focal_length in metres (0: focus distance >> focal length). frame: (x, y, width, "
        "height) in pixels of the full frame this image is a window of (a render border), for "
        "Window coordinates.");
  c.def("camera_rays", &camera_rays,
        "The camera's primary rays through the pixel centres, bottom row first: (origins, directions), "
        "each (width * height, 3), as the renderer generates them (clip start included).");
}

}  // namespace ppm::python
