// Python bindings of a share of a still's passes and their merge (ppm/share.h). A Share pickles
// as a dict of numbers and numpy arrays (to_dict), so it travels to and from other machines
// (dask) and to files (numpy.savez) as plain data.
#include "ppm/share.h"
#include "python/bindings.h"
#include "python/convert.h"

#include <pybind11/stl.h>

#include <cstring>

namespace py = pybind11;
using namespace ppm;

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

py::array_t<float> image_array(const Share& s, const std::vector<float>& values, int channels) {
  return py::array_t<float>({py::ssize_t(s.height), py::ssize_t(s.width), py::ssize_t(channels)}, values.data());
}

// `values` from array `d[key]` of (height, width, channels) floats.
void read_floats(const py::dict& d, const char* key, const Share& s, int channels, float* out) {
  const FloatArray a = py_convert::array_or_null<FloatArray>(d[key]);
  if (!a || a.ndim() != 3 || a.shape(0) != s.height || a.shape(1) != s.width || a.shape(2) != channels)
    throw std::invalid_argument(std::string("share: '") + key + "' must be a (height, width, " +
                                std::to_string(channels) + ") float array");
  std::memcpy(out, a.data(), static_cast<size_t>(a.size()) * sizeof(float));
}

// (first, count) pairs.
py::list ranges_list(const Share& s) {
  py::list out;
  for (const PassRange& r : s.ranges) out.append(py::make_tuple(r.first, r.count));
  return out;
}

py::dict to_dict(const Share& s) {
  py::dict d;
  d["width"] = s.width;
  d["height"] = s.height;
  d["seed"] = s.seed;
  d["photons_per_pass"] = s.photons_per_pass;
  d["alpha"] = s.alpha;
  d["ranges"] = ranges_list(s);
  d["image"] = image_array(s, s.image, 4);
  std::vector<float> moments(s.pixels() * 4);
  std::memcpy(moments.data(), s.errors.data(), moments.size() * sizeof(float));
  d["moments"] = image_array(s, moments, 4);
  d["light_passes"] = s.seen.empty() ? py::object(py::none()) : py::object(image_array(s, s.seen, 6));
  return d;
}

Share from_dict(const py::dict& d) {
  for (const char* key : {"width", "height", "seed", "photons_per_pass", "alpha", "ranges", "image", "moments"})
    if (!d.contains(key)) throw std::invalid_argument(std::string("share: no '") + key + "'");
  Share s;
  try {
    s.width = d["width"].cast<int>();
    s.height = d["height"].cast<int>();
    s.seed = d["seed"].cast<uint64_t>();
    s.photons_per_pass = d["photons_per_pass"].cast<uint64_t>();
    s.alpha = d["alpha"].cast<double>();
    for (const auto& r : d["ranges"].cast<std::vector<std::pair<uint64_t, uint64_t>>>())
      s.ranges.push_back(PassRange{r.first, r.second});
  } catch (const py::cast_error&) {
    throw std::invalid_argument("share: width, height, seed, photons_per_pass, alpha or ranges has the wrong type");
  }
  if (s.width < 1 || s.height < 1 || static_cast<double>(s.width) * s.height > 1e9)
    throw std::invalid_argument("share: width and height must be positive");
  s.image.resize(s.pixels() * 4);
  s.errors.resize(s.pixels());
  read_floats(d, "image", s, 4, s.image.data());
  read_floats(d, "moments", s, 4, reinterpret_cast<float*>(s.errors.data()));
  if (d.contains("light_passes") && !d["light_passes"].is_none()) {
    s.seen.resize(s.pixels() * 6);
    read_floats(d, "light_passes", s, 6, s.seen.data());
  }
  s.validate();
  return s;
}

}  // namespace

namespace ppm::python {

void bind_share(py::module_& m) {
  static_assert(sizeof(PixelErrorStats) == 4 * sizeof(float), "moments are 4 floats a pixel");
  py::class_<Share>(m, "Share",
                    "A share of a still's passes (Renderer.share() with radius_schedule='global'): the mean of "
                    "its passes per pixel and the error estimate's moments. Shares of one still merge exactly "
                    "(merge_shares): N shares of K passes give the image and error estimate of one N*K-pass render.")
      .def_readonly("width", &Share::width)
      .def_readonly("height", &Share::height)
      .def_readonly("seed", &Share::seed)
      .def_property_readonly("passes", &Share::passes)
      .def_property_readonly("ranges", &ranges_list, "the passes it holds: (first, count) pairs")
      .def("image", [](const Share& s) { return image_array(s, s.image, 4); },
           "Linear RGBA float32 (H, W, 4), top row first, RGB premultiplied: the mean of the passes.")
      .def(
          "error",
          [](const Share& s, double confidence) {
            return py_convert::channel_views(s.height, s.width, share_error_image(s, confidence), 3,
                                             {{"bias", 0, 1}, {"noise", 1, 1}, {"luminance", 2, 1}});
          },
          py::arg("confidence") = 0.95, "Per pixel bias, noise and luminance, as Renderer.error().")
      .def(
          "error_stats", [](const Share& s, double confidence) { return image_error_dict(share_error(s, confidence)); },
          py::arg("confidence") = 0.95, "The image's error estimate, as Renderer.stats()['error'].")
      .def("light_passes",
           [](const Share& s) -> py::object {
             if (s.seen.empty()) return py::none();
             return py_convert::channel_views(s.height, s.width, s.seen, 6, {{"Emit", 0, 3}, {"Env", 3, 3}});
           },
           "With light_passes=True: the Emit and Env means, as Renderer.light_passes(); else None.")
      .def("to_dict", &to_dict, "Plain data: numbers, (first, count) pairs and float32 arrays.")
      .def_static("from_dict", &from_dict, py::arg("data"), "The Share to_dict() gave; checks every field.")
      .def(py::pickle([](const Share& s) { return to_dict(s); }, [](const py::dict& d) { return from_dict(d); }));
  m.def(
      "merge_shares",
      [](const std::vector<const Share*>& shares) {
        if (shares.empty()) throw std::invalid_argument("merge_shares: no shares");
        Share total;
        {
          py::gil_scoped_release release;
          for (const Share* s : shares) merge_into(total, *s);
        }
        return total;
      },
      py::arg("shares"),
      "One Share of all their passes. Raises ValueError if they are not shares of one still (size, seed, alpha, "
      "photons_per_pass) or hold a pass twice.");
}

}  // namespace ppm::python
