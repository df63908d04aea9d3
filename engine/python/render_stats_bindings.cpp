// What a render reports (ppm/render_stats.h, the error estimate's ImageError) as Python dicts:
// Renderer.stats() and Share.error_stats().
#include "python/bindings.h"

#include <pybind11/stl.h>

namespace py = pybind11;

namespace ppm::python {

py::dict image_error_dict(const ImageError& e) {
  py::dict error;
  error["relative"] = e.relative;
  error["bias"] = e.bias;
  error["noise"] = e.noise;
  error["anti_aliasing"] = e.anti_aliasing;
  error["bound"] = e.bound;
  error["pixel_p95"] = e.pixel_p95;
  error["confidence"] = e.confidence;
  return error;
}

namespace {

py::dict memory_dict(const RenderStats& s) {
  py::dict memory;
  memory["scene"] = s.memory.scene;
  memory["hit_points"] = s.memory.hit_points;
  memory["pixels"] = s.memory.pixels;
  memory["photons"] = s.memory.photons;
  memory["index"] = s.memory.index;
  return memory;
}

py::dict seconds_dict(const RenderStats& s) {
  py::dict t;
  t["eye_pass"] = s.eye_seconds;
  t["density_radius"] = s.density_radius_seconds;
  t["direct_light"] = s.direct_seconds;
  t["photon_trace"] = s.photon.trace_seconds;
  t["index_build"] = s.photon.index_seconds;
  t["gather"] = s.photon.gather_seconds;
  t["progressive_update"] = s.update_seconds;
  t["total"] = s.total_seconds;
  return t;
}

}  // namespace

py::dict stats_dict(const RenderStats& s) {
  py::dict d;
  d["passes"] = s.passes;
  d["photons_emitted"] = s.photons_emitted;
  d["photons_deposited"] = s.photons_deposited;
  d["hit_points"] = s.hit_points;
  d["hit_point_storage"] = s.hit_point_storage;
  d["direct_samples"] = s.direct_samples;
  d["threads"] = s.threads;
  d["cancelled"] = s.cancelled;
  d["pass_done"] = s.pass_done;
  d["memory_bytes"] = s.memory.total();
  d["memory"] = memory_dict(s);
  d["initial_radius_mean"] = s.initial_radius_mean;
  d["photon_spacing"] = s.photon_spacing;
  d["volume_photon_spacing"] = s.volume_photon_spacing;
  d["radii_widened"] = s.radii_widened;
  d["radius_mean"] = s.radius_mean;
  d["seconds"] = seconds_dict(s);
  d["skipped"] = s.skipped;
  d["error"] = image_error_dict(s.error);
  d["target_error_reached"] = s.target_error_reached;
  return d;
}

}  // namespace ppm::python
