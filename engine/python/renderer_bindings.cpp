// Python bindings of the settings and the renderer. run() releases the GIL;
// the progress callback and Ctrl-C checks take it back briefly.
#include "base/memory_budget.h"
#include "ppm/renderer.h"
#include "python/convert.h"

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <functional>
#include <map>

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

// Every setting by name: how to read it and how to write it from Python.
struct SettingAccess {
  std::function<py::object(const Settings&)> get;
  std::function<void(Settings&, const py::handle&)> set;
  const char* doc;
};

template <class T>
SettingAccess number(T Settings::*field, const char* doc) {
  return {[field](const Settings& s) { return py::cast(s.*field); },
          [field](Settings& s, const py::handle& v) { s.*field = v.cast<T>(); }, doc};
}

template <class E>
SettingAccess enumeration(E Settings::*field, std::vector<std::pair<const char*, E>> names, const char* doc,
                          const char* key) {
  return {[field, names](const Settings& s) {
            for (const auto& [n, e] : names)
              if (s.*field == e) return py::cast(std::string(n));
            return py::cast(std::string("?"));
          },
          [field, names, key](Settings& s, const py::handle& v) {
            const std::string value = v.cast<std::string>();
            std::string options;
            for (const auto& [n, e] : names) {
              if (value == n) {
                s.*field = e;
                return;
              }
              options += std::string(options.empty() ? "'" : ", '") + n + "'";
            }
            throw std::invalid_argument(std::string("settings: ") + key + " must be one of " + options + ", not '" +
                                        printable(value) + "'");
          },
          doc};
}

const std::map<std::string, SettingAccess>& setting_table() {
  static const std::map<std::string, SettingAccess> table = {
      {"photons_per_pass", number(&Settings::photons_per_pass, "photons traced per pass")},
      {"alpha", number(&Settings::alpha, "radius reduction alpha in (0, 1)")},
      {"threshold", number(&Settings::threshold, "P of the cross-generation rule (1 = classic PPM)")},
      {"max_bounces", number(&Settings::max_bounces, "longest photon path / eye specular chain")},
      {"light_path_limits", number(&Settings::light_path_limits,
                                   "honour total/diffuse/glossy/transmission_bounces as Cycles' Light Paths")},
      {"total_bounces", number(&Settings::total_bounces, "light_path_limits: scatterings of a full path")},
      {"diffuse_bounces", number(&Settings::diffuse_bounces, "light_path_limits: diffuse scatterings")},
      {"glossy_bounces", number(&Settings::glossy_bounces, "light_path_limits: glossy scatterings")},
      {"transmission_bounces",
       number(&Settings::transmission_bounces, "light_path_limits: transmission scatterings")},
      {"samples_per_pixel", number(&Settings::samples_per_pixel, "jittered eye samples per pixel")},
      {"seed", number(&Settings::seed, "random seed")},
      {"threads", number(&Settings::threads, "worker threads, 0 = all cores")},
      {"initial_radius", number(&Settings::initial_radius, "initial gather radius in metres, 0 = automatic")},
      {"initial_radius_pixels",
       number(&Settings::initial_radius_pixels, "automatic initial radius in pixel footprints")},
      {"density_radius", number(&Settings::density_radius,
                                "widen the automatic initial radius where one pass's photons are sparser than pixels")},
      {"progress_interval", number(&Settings::progress_interval, "seconds between progress callbacks")},
      {"direct_light", enumeration(&Settings::direct_light,
                                   {{"sampled", DirectLight::Sampled}, {"photons", DirectLight::Photons}},
                                   "'sampled': light sampling + photons for indirect; 'photons': photons carry all",
                                   "direct_light")},
      {"gather", enumeration(&Settings::gather,
                             {{"hit_points", GatherOrganisation::HitPoints}, {"photons", GatherOrganisation::Photons}},
                             "which set the grid organises: 'hit_points' (photons query) or 'photons'", "gather")},
      {"hit_points", enumeration(&Settings::hit_points,
                                 {{"fixed", HitPointMode::Fixed}, {"stochastic", HitPointMode::Stochastic}},
                                 "'fixed' (PPM: one eye pass) or 'stochastic' (SPPM: new eye samples each pass)",
                                 "hit_points")},
      {"hit_point_storage",
       enumeration(&Settings::hit_point_storage,
                   {{"auto", HitPointStorage::Auto}, {"kept", HitPointStorage::Kept},
                    {"streamed", HitPointStorage::Streamed}},
                   "fixed hit points: 'kept' for the render, 'streamed' (made again each pass, 48 bytes each "
                   "kept) or 'auto' (kept where memory allows)",
                   "hit_point_storage")},
      {"dof_mode", enumeration(&Settings::dof_mode,
                               {{"off", DofMode::Off}, {"post", DofMode::Post}, {"lens", DofMode::Lens}},
                               "depth of field: 'off', 'post' (blur by depth) or 'lens' (thin-lens sampling)",
                               "dof_mode")},
      {"dof_post_preset", enumeration(&Settings::dof_post_preset,
                                      {{"thin_lens", DofPostPreset::ThinLens},
                                       {"report_thirds", DofPostPreset::ReportThirds}},
                                      "POST blur: 'thin_lens' circle of confusion or the report's 'report_thirds'",
                                      "dof_post_preset")},
      {"dof_max_radius", number(&Settings::dof_max_radius, "POST: largest blur radius in pixels")},
      {"scene_analysis", number(&Settings::scene_analysis, "skip work the scene cannot use (False: benchmarks)")},
      {"transparent_background",
       number(&Settings::transparent_background, "camera rays that escape leave alpha 0 (Film > Transparent)")},
      {"transparent_glass", number(&Settings::transparent_glass,
                                   "with transparent_background: also rays escaping through smooth glass")},
      {"target_error", number(&Settings::target_error,
                              "stop once the image's estimated relative error is at most this (0: off)")},
      {"error_confidence",
       number(&Settings::error_confidence, "confidence of the error estimate's noise bound, in (0, 1)")},
      {"error_min_passes", number(&Settings::error_min_passes, "passes before target_error can stop a run")},
      {"light_passes", number(&Settings::light_passes,
                              "keep the emission and the world camera rays see at no bounce apart (light_passes())")},
      {"component_passes",
       number(&Settings::component_passes,
              "keep Diffuse, Glossy and Transmission Direct, Indirect and Color and the caustic part apart "
              "(component_passes())")},
      {"photon_guiding", number(&Settings::photon_guiding,
                                "guide point, sphere, spot and area lights' photons towards the pixels the error "
                                "estimate finds noisiest")},
      {"adaptive_samples", number(&Settings::adaptive_samples,
                                  "stochastic hit points: up to this many eye samples a pixel each pass where the "
                                  "error estimate finds the pixel noisiest (1: one everywhere)")},
      {"radius_schedule",
       enumeration(&Settings::radius_schedule,
                   {{"progressive", RadiusSchedule::Progressive}, {"global", RadiusSchedule::Global}},
                   "stochastic hit points: 'progressive' (per pixel, with the threshold P) or 'global' (from the "
                   "pass's index, Knaus & Zwicker 2011: passes render apart and merge, share())",
                   "radius_schedule")},
      {"first_pass", number(&Settings::first_pass,
                            "with radius_schedule 'global': the index of the first pass this renderer renders")},
      {"grid", enumeration(&Settings::grid, {{"quantile", GridKind::Quantile}, {"hash", GridKind::Hash}},
                           "spatial index: 'quantile' grid or 'hash'ed uniform grid", "grid")},
  };
  return table;
}

Settings settings_from(const py::dict& values) {
  Settings s;
  const auto& table = setting_table();
  for (const auto& [key, value] : values) {
    const std::string name = printable(py::str(key));
    const auto it = table.find(name);
    if (it == table.end()) {
      std::string known;
      for (const auto& [k, a] : table) known += (known.empty() ? "" : ", ") + k;
      throw std::invalid_argument("settings: unknown setting '" + name + "' (known: " + known + ")");
    }
    try {
      it->second.set(s, value);
    } catch (const py::cast_error&) {
      throw std::invalid_argument("settings: " + name + " has the wrong type");
    }
  }
  s.validate();
  // Radii whose square stays finite (r^2 would overflow to inf above ~1e154 m).
  if (s.initial_radius > kMaxCoordinate)
    throw std::invalid_argument("settings: initial_radius must be at most 1e30 m");
  if (s.initial_radius_pixels > 1e6) throw std::invalid_argument("settings: initial_radius_pixels must be at most 1e6");
  return s;
}

py::dict settings_dict(const Settings& s) {
  py::dict d;
  for (const auto& [k, a] : setting_table()) d[py::str(k)] = a.get(s);
  return d;
}

}  // namespace

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

// A readback of every pixel (image, passes, error), made with the GIL released.
template <class Read>
std::vector<float> read_released(Read&& read) {
  py::gil_scoped_release release;
  return read();
}

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
  py::dict memory;
  memory["scene"] = s.memory.scene;
  memory["hit_points"] = s.memory.hit_points;
  memory["pixels"] = s.memory.pixels;
  memory["photons"] = s.memory.photons;
  memory["index"] = s.memory.index;
  d["memory"] = memory;
  d["initial_radius_mean"] = s.initial_radius_mean;
  d["photon_spacing"] = s.photon_spacing;
  d["radii_widened"] = s.radii_widened;
  d["radius_mean"] = s.radius_mean;
  py::dict t;
  t["eye_pass"] = s.eye_seconds;
  t["density_radius"] = s.density_radius_seconds;
  t["direct_light"] = s.direct_seconds;
  t["photon_trace"] = s.photon.trace_seconds;
  t["index_build"] = s.photon.index_seconds;
  t["gather"] = s.photon.gather_seconds;
  t["progressive_update"] = s.update_seconds;
  t["total"] = s.total_seconds;
  d["seconds"] = t;
  d["skipped"] = s.skipped;
  d["error"] = image_error_dict(s.error);
  d["target_error_reached"] = s.target_error_reached;
  return d;
}

}  // namespace

void bind_renderer(py::module_& m) {
  // A render the machine has no memory for (memory_budget.h): MemoryError, with its message.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ppm::MemoryShortage& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    }
  });
  py::class_<Settings>(m, "Settings", "Render settings; unknown names are an error.")
      .def(py::init([](const py::kwargs& kw) { return settings_from(kw); }))
      .def("as_dict", &settings_dict)
      .def("__repr__", [](const Settings& s) { return "Settings(" + py::str(settings_dict(s)).cast<std::string>() + ")"; })
      .def("__getattr__", [](const Settings& s, const std::string& name) {
        const auto it = setting_table().find(name);
        if (it == setting_table().end()) throw py::attribute_error("Settings has no setting '" + name + "'");
        return it->second.get(s);
      });
  m.def("default_settings", []() { return settings_dict(Settings{}); }, "The default settings as a dict.");

  py::class_<Renderer>(m, "Renderer", "Progressive photon mapping of a Scene.")
      .def(py::init([](std::shared_ptr<Scene> scene, const py::object& settings, const py::kwargs& overrides) {
             if (!scene) throw std::invalid_argument("Renderer: scene is None");
             py::dict values;
             if (py::isinstance<Settings>(settings)) values = settings_dict(settings.cast<Settings>());
             else if (py::isinstance<py::dict>(settings)) values = settings.cast<py::dict>();
             else if (!settings.is_none()) throw std::invalid_argument("Renderer: settings must be a Settings, a dict or None");
             for (const auto& [k, v] : overrides) values[k] = v;
             const Settings s = settings_from(values);
             scene->build();
             scene->check_energy_range(s.path_bounces());
             return std::make_unique<Renderer>(scene, s);
           }),
           py::arg("scene"), py::arg("settings") = py::none())
      .def(
          "run",
          [](Renderer& r, uint64_t passes, double seconds, const py::object& callback, double pause_after) {
            std::function<bool(const Progress&)> poll = [&](const Progress& p) {
              py::gil_scoped_acquire gil;
              if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C cancels
              if (callback.is_none()) return true;
              py::dict info;
              info["passes"] = p.passes;
              info["photons_emitted"] = p.photons_emitted;
              info["seconds"] = p.seconds;
              info["pass_done"] = p.pass_done;
              const py::object result = callback(info);
              if (result.is_none()) return true;
              const bool numpy_flag = py::hasattr(result, "dtype") && py::hasattr(result, "ndim") &&
                                      result.attr("ndim").cast<int>() == 0 &&
                                      std::string("biu").find(py::str(result.attr("dtype").attr("kind")).cast<std::string>()) != std::string::npos;
              if (!py::isinstance<py::bool_>(result) && !py::isinstance<py::int_>(result) && !numpy_flag)
                throw std::invalid_argument("run: the callback must return None, True (go on) or False (cancel), not " +
                                            std::string(py::str(py::type::of(result).attr("__name__"))));
              return PyObject_IsTrue(result.ptr()) == 1;
            };
            py::gil_scoped_release release;
            return r.run(passes, seconds, poll, pause_after);
          },
          py::arg("passes") = 0, py::arg("seconds") = 0.0, py::arg("callback") = py::none(),
          py::arg("pause_after") = 0.0,
          "Runs passes until `passes` are done or `seconds` have passed (0 = no limit for either). "
          "callback(dict(passes, photons_emitted, seconds, pass_done)) is called often (pass_done: the share of "
          "the pass in progress already in the image); returning False cancels. pause_after > 0: a "
          "stochastic pass still running that many seconds after the start returns at the end of its band "
          "of rows, its finished bands in the image (stats()['pass_done']); the next run() continues it. "
          "Returns the number of passes completed.")
      .def("share", &Renderer::share, py::call_guard<py::gil_scoped_release>(),
           "With radius_schedule='global': the passes so far as a Share, to merge with other renderers' "
           "(merge_shares), e.g. on other machines with first_pass set to the passes before theirs.")
      .def("cancel", &Renderer::cancel, "Stops a run() in progress (callable from another thread).")
      .def("image",
           [](const Renderer& r) {
             std::vector<float> rgba = read_released([&] { return r.image(); });
             // The array takes the pixels over (no copy: at 4K a copy is another 130 MB).
             auto* owned = new std::vector<float>(std::move(rgba));
             py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
             return py::array_t<float>({py::ssize_t(r.height()), py::ssize_t(r.width()), py::ssize_t(4)},
                                       owned->data(), owner);
           },
           "Linear RGBA float32 image of shape (H, W, 4), top row first; alpha = 1.")
      .def("stats", [](const Renderer& r) { return stats_dict(r.stats()); })
      .def("light_passes",
           [](const Renderer& r) {
             std::vector<float> values = read_released([&] { return r.light_passes(); });
             return channel_views(r.height(), r.width(), values, 6, {{"Emit", 0, 3}, {"Env", 3, 3}});
           },
           "With light_passes=True: what camera rays see at no bounce, as Cycles' Emit and Env passes: dict of "
           "(H, W, 3) float32, top row first, 'Emit' (surfaces' and lights' emission) and 'Env' (the world). "
           "What is seen through mirrors and glass is in neither (Cycles counts it as glossy or transmission "
           "light).")
      .def("photon_guide",
           [](const Renderer& r) {
             const PhotonGuide guide = r.photon_guide();
             py::list out;
             for (int s = 0; s < guide.slots(); ++s) {
               const std::vector<double> p = guide.probabilities(s);
               py::array_t<double> a({PhotonGuide::kRings, PhotonGuide::kSectors});
               std::copy(p.begin(), p.end(), a.mutable_data());
               out.append(a);
             }
             return out;
           },
           "With photon_guiding=True: per guided light (point, sphere and area lights, spots of a radius, in the "
           "scene's order), the probability of each direction bin (rings of cos(theta) from -1, or 0 for an area "
           "light in its frame, to 1; sectors of phi); uniform (1/512 each) before the guide has learned.")
      .def("component_passes",
           [](const Renderer& r) {
             std::vector<float> values = read_released([&] { return r.component_passes(); });
             return channel_views(r.height(), r.width(), values, 30,
                                  {{"DiffDir", 0, 3}, {"DiffInd", 3, 3}, {"GlossDir", 6, 3}, {"GlossInd", 9, 3},
                                   {"TransDir", 12, 3}, {"TransInd", 15, 3}, {"Caustic", 18, 3},
                                   {"DiffCol", 21, 3}, {"GlossCol", 24, 3}, {"TransCol", 27, 3}});
           },
           "With component_passes=True: the light by Cycles' passes, dict of (H, W, 3) float32, top row first. "
           "DiffDir, DiffInd, GlossDir, GlossInd, TransDir and TransInd are radiance (with light_passes' Emit and "
           "Env they add up to image(), but for a 'post' depth-of-field blur); Cycles stores them divided by "
           "DiffCol, GlossCol and TransCol, the albedo of each class at the first surface. Caustic: the light of "
           "photons that came by mirrors and glass only, part of the Indirect ones.")
      .def("denoising_features",
           [](Renderer& r, int samples_per_pixel) {
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
           },
           py::arg("samples_per_pixel") = 0,
           "Cycles' Denoising Albedo and Denoising Normal: dict of (H, W, 3) float32 arrays 'albedo' (linear "
           "RGB) and 'normal' (world space), top row first, from an eye pass of samples_per_pixel samples a "
           "pixel (0: the settings'). As Cycles, each sample's are those of the first surface its path does "
           "not follow as a mirror or smooth glass, through the tint of those it does; zero where it sees only "
           "background or emitters.")
      .def("error",
           [](const Renderer& r) {
             std::vector<float> values = read_released([&] { return r.error_image(); });
             return channel_views(r.height(), r.width(), values, 3,
                                  {{"bias", 0, 1}, {"noise", 1, 1}, {"luminance", 2, 1}});
           },
           "The estimated error per pixel, (H, W) float32 arrays, top row first, in luminance: 'bias' (signed: "
           "the image minus the truth, expected), 'noise' (half-width at settings error_confidence), "
           "'luminance' (the pixel's). The bound is abs(bias) + noise; stats()['error'] gives the image's.")
      .def_property_readonly("settings", [](const Renderer& r) { return settings_dict(r.settings()); });
}
