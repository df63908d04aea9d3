// Participating media from Python (scene/medium.h): Scene.add_medium, Scene.set_world_medium,
// Scene.set_material_medium, and add_material's `medium` and `surface` keywords (add_material as
// material_bindings.cpp binds it, wrapped: bind_scene calls this after bind_materials).
#include "python/bindings.h"
#include "python/convert.h"
#include "python/node_program_bindings.h"
#include "scene/scene.h"

#include <pybind11/pybind11.h>

#include <cmath>
#include <memory>
#include <string>

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

// A medium named `name` or an index; None: -1.
int medium_index(const Scene& s, const py::handle& medium, const std::string& what) {
  if (medium.is_none()) return -1;
  if (py::isinstance<py::str>(medium)) {
    const std::string name = medium.cast<std::string>();
    for (size_t i = 0; i < s.added_media(); ++i)
      if (s.media()[i].name == name) return static_cast<int>(i);
    fail(what, "no medium named '" + printable(name) + "' (add it with add_medium first)");
  }
  if (py::isinstance<py::int_>(medium)) return medium.cast<int>();
  fail(what, "medium must be a medium's name, its index or None");
}

double finite_parameter(double x, const std::string& what, const std::string& field) {
  if (!std::isfinite(x)) fail(what, field + " must be a finite number");
  return x;
}

Phase phase_from(const std::string& kind, double anisotropy, double alpha, double backscatter, double ior,
                 double diameter, const std::string& what) {
  finite_parameter(anisotropy, what, "anisotropy");
  if (std::fabs(anisotropy) > 1.0) fail(what, "anisotropy must be in [-1, 1] (clamped to 0.999 as Cycles does)");
  if (kind == "henyey_greenstein") return henyey_greenstein_phase(anisotropy);
  if (kind == "rayleigh") return rayleigh_phase();
  if (kind == "draine") return draine_phase(anisotropy, finite_parameter(alpha, what, "alpha"));
  if (kind == "fournier_forand")
    return fournier_forand_phase(finite_parameter(backscatter, what, "backscatter"), finite_parameter(ior, what, "ior"));
  if (kind == "mie") {
    if (!(diameter >= 0.0 && diameter <= 50.0)) fail(what, "diameter must be in [0, 50] micrometres");
    return mie_phase(diameter);
  }
  fail(what, "phase must be one of 'henyey_greenstein', 'rayleigh', 'draine', 'fournier_forand', 'mie', not '" +
                 printable(kind) + "'");
}

// What varies in a medium: `program` (a node program's dict) and `terms` (dicts of sigma_a,
// sigma_s, emission and the program's output `input` scaling them).
std::shared_ptr<MediumField> field_from(const py::object& program, const py::object& terms, const std::string& what) {
  if (program.is_none() && terms.is_none()) return nullptr;
  if (program.is_none() || terms.is_none()) fail(what, "give a program and the terms it scales, or neither");
  auto f = std::make_shared<MediumField>();
  f->program = program_from(program, what);
  for (const py::handle& item : terms.cast<py::list>()) {
    const py::dict d = py::reinterpret_borrow<py::object>(item).cast<py::dict>();
    for (const auto& [key, value] : d) {
      const std::string k = key.cast<std::string>();
      if (k != "sigma_a" && k != "sigma_s" && k != "emission" && k != "input")
        fail(what, "a term has no field '" + printable(k) + "' (sigma_a, sigma_s, emission, input)");
    }
    MediumTerm t;
    if (d.contains("sigma_a")) t.sigma_a = color(d["sigma_a"], what, "terms' sigma_a");
    if (d.contains("sigma_s")) t.sigma_s = color(d["sigma_s"], what, "terms' sigma_s");
    if (d.contains("emission")) t.emission = color(d["emission"], what, "terms' emission");
    const int input = d.contains("input") ? d["input"].cast<int>() : 0;
    if (input < 0 || input > 0xffff) fail(what, "a term's input must be one of the program's outputs");
    t.input = static_cast<uint16_t>(input);
    f->terms.push_back(t);
  }
  return f;
}

uint32_t add_medium(Scene& s, const std::string& name, const py::object& sigma_a, const py::object& sigma_s,
                    const py::object& emission, const std::string& phase, double anisotropy, double alpha,
                    double backscatter, double ior, double diameter, const py::object& program,
                    const py::object& terms) {
  const std::string what = "medium '" + checked_name(name, "medium") + "'";
  for (size_t i = 0; i < s.added_media(); ++i)
    if (s.media()[i].name == name) fail(what, "a medium of that name exists already");
  Medium m;
  m.name = name;
  m.c.sigma_a = color(sigma_a, what, "sigma_a");
  m.c.sigma_s = color(sigma_s, what, "sigma_s");
  m.c.emission = color(emission, what, "emission");
  m.c.phase = phase_from(phase, anisotropy, alpha, backscatter, ior, diameter, what);
  m.field = field_from(program, terms, what);
  return s.add_medium(std::move(m));
}

}  // namespace

namespace ppm::python {

void bind_media(SceneClass& cls) {
  cls.def("add_medium", &add_medium, py::arg("name"), py::arg("sigma_a") = 0.0, py::arg("sigma_s") = 0.0,
          py::arg("emission") = 0.0, py::arg("phase") = "henyey_greenstein", py::arg("anisotropy") = 0.0,
          py::arg("alpha") = 0.0, py::arg("backscatter") = 0.1, py::arg("ior") = 1.33, py::arg("diameter") = 10.0,
          py::arg("program") = py::none(), py::arg("terms") = py::none(),
          "A homogeneous medium: RGB absorption sigma_a, scattering sigma_s (per metre, each a colour or a "
          "number) and emission (radiance per metre), with a phase function ('henyey_greenstein' with "
          "`anisotropy`, 'rayleigh', 'draine' (anisotropy, alpha), 'fournier_forand' (backscatter, ior), 'mie' "
          "(diameter in micrometres)). A medium that varies in space adds `terms` (dicts of sigma_a, sigma_s, "
          "emission and `input`), each times output `input` of node `program` (as add_material's) run where "
          "the path is, inside the object that bounds it (its coordinates; negative outputs count as 0). NaN, "
          "Inf, negative values or coefficients above 1e30 are a ValueError naming the medium and field. "
          "Returns its index; materials (add_material(medium=)) and the world (set_world_medium, homogeneous "
          "only) name it. Media render with hit_points='stochastic'.");
  cls.def_property_readonly(
      "media",
      [](const Scene& s) {
        py::list names;
        for (size_t i = 0; i < s.added_media(); ++i) names.append(s.media()[i].name);
        return names;
      },
      "The media's names, by index.");
  cls.def_property("majorant_grids", &Scene::majorant_grids, &Scene::set_majorant_grids,
                   "Whether media that vary in space get a majorant grid where it pays (True by default): a "
                   "coarse grid of bounds over the object, so that paths through a sparse cloud take tentative "
                   "collisions at the rate of where they are, not of its densest voxel. False: one majorant a "
                   "medium. The image is the same but for noise.");
  cls.def_property_readonly(
      "medium_majorants",
      [](Scene& s) {
        s.build();
        py::list out;
        for (size_t i = s.added_media(); i < s.media().size(); ++i) {
          const Medium& m = s.media()[i];
          py::dict d;
          d["name"] = m.name;
          d["majorant"] = max_component(m.sigma_t_bound);
          if (!m.majorant_grids.empty()) {
            const MajorantGrid& g = *m.majorant_grids[0];
            d["cells"] = py::make_tuple(g.dims()[0], g.dims()[1], g.dims()[2]);
            d["mean_cell"] = g.mean_majorant();
          }
          out.append(d);
        }
        return out;
      },
      "Per object's copy of a medium that varies (build() makes them): its name, its one majorant, and "
      "where it has a majorant grid the grid's cells along x, y, z and their mean majorant.");
  cls.def_property_readonly("has_media", &Scene::has_media,
                            "Whether anything renders through media: a world medium, a material's medium, or a "
                            "material without a surface.");
  cls.def(
      "set_world_medium",
      [](Scene& s, const py::object& medium) { s.set_world_medium(medium_index(s, medium, "world")); },
      py::arg("medium"), "The medium (name or index; None: none) filling all space outside meshes with media.");
  cls.def(
      "set_material_medium",
      [](Scene& s, uint32_t material, const py::object& medium, bool surface) {
        s.set_material_medium(material, medium_index(s, medium, "material " + std::to_string(material)), surface);
      },
      py::arg("material"), py::arg("medium"), py::arg("surface") = true,
      "Material `material` carries `medium` (name or index; None: none) inside the closed mesh it is on; "
      "surface=False makes it a boundary only (Blender: a Volume output alone): rays cross it unchanged.");
  // add_material(..., medium=None, surface=True): the other keywords go to add_material as bound in
  // scene_bindings.cpp, then the medium is set.
  py::object original = cls.attr("add_material");
  cls.attr("add_material") = py::cpp_function(
      [original](py::object self, py::args args, py::kwargs kwargs) -> py::object {
        py::object medium = py::none();
        bool surface = true;
        if (kwargs.contains("medium")) medium = kwargs.attr("pop")("medium");
        if (kwargs.contains("surface")) surface = kwargs.attr("pop")("surface").cast<bool>();
        Scene& s = self.cast<Scene&>();
        // Checked before the material is added, so that a bad medium adds nothing.
        const int index = medium_index(s, medium, "material");
        if (index >= static_cast<int>(s.added_media())) fail("material", "medium index out of range");
        py::object result = original(self, *args, **kwargs);
        if (index >= 0 || !surface) s.set_material_medium(result.cast<uint32_t>(), index, surface);
        return result;
      },
      py::name("add_material"), py::is_method(cls),
      py::doc((std::string(py::str(original.attr("__doc__"))) +
               "\n\nmedium: a medium's name or index (add_medium) filling the closed mesh the material is on; "
               "surface=False: the material has no surface, only the medium's boundary.")
                  .c_str()));
}

}  // namespace ppm::python
