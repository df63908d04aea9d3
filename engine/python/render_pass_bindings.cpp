// Python bindings of what a renderer reads back: its image and passes (Cycles' Emit and Env, the
// light components, Denoising Albedo and Normal), its error estimate per pixel and its photon
// guide, as numpy arrays; every readback of all the pixels is made with the GIL released.
#include "python/bindings.h"
#include "python/convert.h"

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

// A readback of every pixel (image, passes, error), made with the GIL released.
template <class Read>
std::vector<float> read_released(Read&& read) {
  py::gil_scoped_release release;
  return read();
}

py::array_t<float> image(const Renderer& r) {
  std::vector<float> rgba = read_released([&] { return r.image(); });
  // The array takes the pixels over (no copy: at 4K a copy is another 130 MB).
  auto* owned = new std::vector<float>(std::move(rgba));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  return py::array_t<float>({py::ssize_t(r.height()), py::ssize_t(r.width()), py::ssize_t(4)}, owned->data(), owner);
}

py::dict light_passes(const Renderer& r) {
  std::vector<float> values = read_released([&] { return r.light_passes(); });
  return channel_views(r.height(), r.width(), values, 6, {{"Emit", 0, 3}, {"Env", 3, 3}});
}

py::dict component_passes(const Renderer& r) {
  std::vector<float> values = read_released([&] { return r.component_passes(); });
  return channel_views(r.height(), r.width(), values, 36,
                       {{"DiffDir", 0, 3}, {"DiffInd", 3, 3}, {"GlossDir", 6, 3}, {"GlossInd", 9, 3},
                        {"TransDir", 12, 3}, {"TransInd", 15, 3}, {"VolumeDir", 18, 3}, {"VolumeInd", 21, 3},
                        {"Caustic", 24, 3}, {"DiffCol", 27, 3}, {"GlossCol", 30, 3}, {"TransCol", 33, 3}});
}

py::dict denoising_features(Renderer& r, int samples_per_pixel) {
  std::vector<float> values;
  {
    py::gil_scoped_release release;
    values = r.denoising_features(samples_per_pixel, [] {
      py::gil_scoped_acquire gil;
      return PyErr_CheckSignals() == 0;  // Ctrl-C cancels
    });
  }
  if (values.empty()) {
    if (PyErr_Occurred()) throw py::error_already_set();
    throw std::runtime_error("denoising_features: cancelled");
  }
  return channel_views(r.height(), r.width(), values, 6, {{"albedo", 0, 3}, {"normal", 3, 3}});
}

py::dict error(const Renderer& r) {
  std::vector<float> values = read_released([&] { return r.error_image(); });
  return channel_views(r.height(), r.width(), values, 3, {{"bias", 0, 1}, {"noise", 1, 1}, {"luminance", 2, 1}});
}

py::list photon_guide(const Renderer& r) {
  const PhotonGuide guide = r.photon_guide();
  py::list out;
  for (int s = 0; s < guide.slots(); ++s) {
    const std::vector<double> p = guide.probabilities(s);
    py::array_t<double> a({PhotonGuide::kRings, PhotonGuide::kSectors});
    std::copy(p.begin(), p.end(), a.mutable_data());
    out.append(a);
  }
  return out;
}

}  // namespace

namespace ppm::python {

void bind_render_passes(RendererClass& c) {
  c.def("image", &image, "Linear RGBA float32 image of shape (H, W, 4), top row first; alpha = 1.");
  c.def("light_passes", &light_passes,
        "With light_passes=True: what camera rays see at no bounce, as Cycles' Emit and Env passes: dict of "
        "(H, W, 3) float32, top row first, 'Emit' (surfaces' and lights' emission) and 'Env' (the world). "
        "What is seen through mirrors and glass is in neither (Cycles counts it as glossy or transmission "
        "light).");
  c.def("photon_guide", &photon_guide,
        "With photon_guiding=True: per guided light (point, sphere and area lights, spots of a radius, in the "
        "scene's order), the probability of each direction bin (rings of cos(theta) from -1, or 0 for an area "
        "light in its frame, to 1; sectors of phi); uniform (1/512 each) before the guide has learned.");
  c.def("component_passes", &component_passes,
        "With component_passes=True: the light by Cycles' passes, dict of (H, W, 3) float32, top row first. "
        "DiffDir, DiffInd, GlossDir, GlossInd, TransDir, TransInd, VolumeDir and VolumeInd are radiance (with "
        "light_passes' Emit and Env they add up to image(), but for a 'post' depth-of-field blur); Cycles stores "
        "the first six divided by DiffCol, GlossCol and TransCol, the albedo of each class at the first surface. "
        "VolumeDir: light sampled where a camera path first scatters in a medium; VolumeInd: the volume photons "
        "there (zero in scenes without media). Caustic: the light of photons that came by mirrors and glass only, "
        "part of the Indirect ones.");
  c.def("denoising_features", &denoising_features, py::arg("samples_per_pixel") = 0,
        "Cycles' Denoising Albedo and Denoising Normal: dict of (H, W, 3) float32 arrays 'albedo' (linear "
        "RGB) and 'normal' (world space), top row first, from an eye pass of samples_per_pixel samples a "
        "pixel (0: the settings'). As Cycles, each sample's are those of the first surface its path does "
        "not follow as a mirror or smooth glass, through the tint of those it does; zero where it sees only "
        "background or emitters.");
  c.def("error", &error,
        "The estimated error per pixel, (H, W) float32 arrays, top row first, in luminance: 'bias' (signed: "
        "the image minus the truth, expected), 'noise' (half-width at settings error_confidence), "
        "'luminance' (the pixel's). The bound is abs(bias) + noise; stats()['error'] gives the image's.");
}

}  // namespace ppm::python
