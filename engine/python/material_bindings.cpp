// Python bindings of Scene.add_material: a material's kind, colours, lobes (dicts), inputs (images
// or a node program) and normal map, translated into a Material for the scene.
#include "python/bindings.h"
#include "python/convert.h"
#include "python/node_program_bindings.h"

#include <algorithm>
#include <vector>

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

// A lobe's reference to one of its material's inputs: an index, or (index, transform).
InputRef input_ref(const py::handle& value, InputRef::Transform default_transform, const std::string& what,
                   const std::string& field) {
  InputRef ref;
  ref.transform = default_transform;
  py::object index = py::reinterpret_borrow<py::object>(value);
  if (py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(value);
    if (pair.size() != 2) fail(what, field + " must be an input index or (index, transform)");
    index = pair[0];
    ref.transform = choice<InputRef::Transform>(py::str(pair[1]),
                                                {{"value", InputRef::Value},
                                                 {"sqrt", InputRef::Sqrt},
                                                 {"fraction", InputRef::Fraction},
                                                 {"complement", InputRef::Complement}},
                                                what, field + " transform");
  }
  const int i = py::cast<int>(index);
  if (i < 0 || i >= kMaxInputs) fail(what, field + " must name an input (0 to " + std::to_string(kMaxInputs - 1) + ")");
  ref.input = static_cast<int8_t>(i);
  return ref;
}

// A lobe dict's keys are the ones add_material documents.
void check_lobe_keys(const py::dict& d, const std::string& what) {
  static const char* const kKeys[] = {"kind",         "weight",  "color",       "tint",
                                      "roughness",    "ior",     "parts",       "layer",
                                      "textured",     "multiscatter", "beckmann", "tint_f0", "color_input",
                                      "roughness_input", "weight_inputs", "stretch", "rotation"};
  for (const auto& [key, value] : d) {
    const std::string k = py::str(key);
    if (std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char* n) { return k == n; }) == std::end(kKeys))
      fail(what, "unknown lobe key '" + printable(k) + "'");
  }
}

LobeKind lobe_kind(const py::dict& d, const std::string& what) {
  return choice<LobeKind>(d.contains("kind") ? py::str(d["kind"]) : py::str("diffuse"),
                          {{"diffuse", LobeKind::Diffuse},
                           {"translucent", LobeKind::Translucent},
                           {"transparent", LobeKind::Transparent},
                           {"conductor", LobeKind::Conductor},
                           {"glossy", LobeKind::Glossy},
                           {"dielectric", LobeKind::Dielectric},
                           {"velvet", LobeKind::Velvet},
                           {"schlick_sheen", LobeKind::SchlickSheen},
                           {"microfiber_sheen", LobeKind::MicrofiberSheen}},
                          what, "lobe kind");
}

// The lobe's references to its material's inputs: color_input, roughness_input, weight_inputs.
void lobe_inputs(const py::dict& d, Lobe& l, const std::string& what) {
  if (d.contains("color_input")) l.color_input = input_ref(d["color_input"], InputRef::Value, what, "color_input");
  if (d.contains("roughness_input"))
    l.roughness_input = input_ref(d["roughness_input"], InputRef::Value, what, "roughness_input");
  if (d.contains("weight_inputs")) {
    const py::sequence refs = py::reinterpret_borrow<py::sequence>(d["weight_inputs"]);
    if (refs.size() > l.weight_inputs.size()) fail(what, "a lobe takes at most 2 weight_inputs");
    for (size_t i = 0; i < refs.size(); ++i) l.weight_inputs[i] = input_ref(refs[i], InputRef::Fraction, what, "weight_inputs");
  }
}

// One lobe of a mixture from a dict (the keys are listed in add_material's documentation);
// `textured`: its colour is the material's texture.
Lobe lobe_from(const py::handle& item, bool& textured, const std::string& what) {
  if (!py::isinstance<py::dict>(item)) fail(what, "each lobe must be a dict");
  const py::dict d = py::reinterpret_borrow<py::dict>(item);
  check_lobe_keys(d, what);
  Lobe l;
  l.kind = lobe_kind(d, what);
  if (d.contains("weight")) l.weight = color(d["weight"], what, "lobe weight");
  if (d.contains("color")) l.color = color(d["color"], what, "lobe color");
  if (d.contains("tint")) l.tint = color(d["tint"], what, "lobe tint");
  if (d.contains("roughness")) l.roughness = py::cast<double>(d["roughness"]);
  if (d.contains("ior")) l.ior = py::cast<double>(d["ior"]);
  if (d.contains("parts"))
    l.parts = choice<uint8_t>(py::str(d["parts"]),
                              {{"both", kReflectionAndRefraction}, {"reflection", kReflection}, {"refraction", kRefraction}},
                              what, "lobe parts");
  if (d.contains("layer")) l.layer = py::cast<bool>(d["layer"]);
  textured = d.contains("textured") && py::cast<bool>(d["textured"]);
  if (d.contains("multiscatter")) l.multiscatter = py::cast<bool>(d["multiscatter"]);
  if (d.contains("beckmann")) l.beckmann = py::cast<bool>(d["beckmann"]);
  if (d.contains("tint_f0")) l.tint_f0 = py::cast<bool>(d["tint_f0"]);
  lobe_inputs(d, l, what);
  if (d.contains("stretch")) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(d["stretch"]);
    if (pair.size() != 2) fail(what, "a lobe's stretch is (along the tangent, across it)");
    l.stretch_x = py::cast<double>(pair[0]);
    l.stretch_y = py::cast<double>(pair[1]);
  }
  if (d.contains("rotation")) l.rotation = py::cast<double>(d["rotation"]);
  if (textured && l.color_input.used()) fail(what, "a lobe is either textured or has a color_input");
  return l;
}

// A mixture's lobes from a list of dicts, into the material (add_lobes: the textured ones' input).
void lobes_from(const py::object& lobes, Material& m, const std::string& what) {
  if (lobes.is_none()) return;
  if (m.kind != MaterialKind::Mixture) fail(what, "lobes are for kind 'mixture' only");
  if (py::isinstance<py::str>(lobes) || !py::isinstance<py::iterable>(lobes)) fail(what, "lobes must be a list");
  std::vector<Lobe> parsed;
  std::vector<bool> textured;
  for (const py::handle item : lobes) {
    bool t = false;
    parsed.push_back(lobe_from(item, t, what));
    textured.push_back(t);
  }
  add_lobes(m, parsed, textured);
}

// A mixture's inputs given as images: (texture index, channel 'rgb', 'alpha' or 'grey') each, read
// at the hit's UV: a node program of image lookups.
void add_image_inputs(NodeProgram& program, const py::object& inputs, const std::string& what) {
  if (inputs.is_none()) return;
  if (py::isinstance<py::str>(inputs) || !py::isinstance<py::iterable>(inputs)) fail(what, "inputs must be a list");
  for (const py::handle item : inputs) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(item);
    if (!py::isinstance<py::sequence>(item) || pair.size() != 2)
      fail(what, "each input must be (texture index, 'rgb' | 'alpha' | 'grey')");
    const int texture = py::cast<int>(pair[0]);
    if (texture < 0) fail(what, "input texture index out of range");
    const auto channel = choice<TextureChannel>(
        py::str(pair[1]),
        {{"rgb", TextureChannel::Rgb}, {"alpha", TextureChannel::Alpha}, {"grey", TextureChannel::Grey}}, what,
        "input channel");
    program.add_image_output(texture, channel);
  }
}

// A mixture's normal map from a dict: input (an index), strength, space ('tangent' or 'world').
NormalMap normal_map_from(const py::object& value, const std::string& what) {
  NormalMap map;
  if (value.is_none()) return map;
  if (!py::isinstance<py::dict>(value)) fail(what, "normal_map must be a dict (input, strength, space)");
  const py::dict d = py::reinterpret_borrow<py::dict>(value);
  for (const auto& [key, item] : d) {
    const std::string k = py::str(key);
    if (k != "input" && k != "strength" && k != "space" && k != "softening" && k != "valid_reflection")
      fail(what, "unknown normal_map key '" + printable(k) + "'");
  }
  if (!d.contains("input")) fail(what, "normal_map needs an input");
  map.input = input_ref(d["input"], InputRef::Value, what, "normal_map input").input;
  if (d.contains("strength")) map.strength = py::cast<double>(d["strength"]);
  if (d.contains("space"))
    map.space = choice<NormalMap::Space>(
        py::str(d["space"]),
        {{"tangent", NormalMap::Tangent}, {"world", NormalMap::World}, {"direct", NormalMap::Direct}}, what,
        "normal_map space");
  if (d.contains("softening"))
    map.softening = choice<BumpSoftening>(py::str(d["softening"]),
                                          {{"none", BumpSoftening::None},
                                           {"chiang", BumpSoftening::Chiang},
                                           {"conty_estevez", BumpSoftening::ContyEstevez}},
                                          what, "normal_map softening");
  if (d.contains("valid_reflection")) map.valid_reflection = py::cast<bool>(d["valid_reflection"]);
  return map;
}

MaterialKind material_kind(const std::string& kind, const std::string& what) {
  return choice<MaterialKind>(kind,
                              {{"diffuse", MaterialKind::Diffuse},
                               {"mirror", MaterialKind::Mirror},
                               {"metal", MaterialKind::Metal},
                               {"glass", MaterialKind::Glass},
                               {"emission", MaterialKind::Emission},
                               {"holdout", MaterialKind::Holdout},
                               {"mixture", MaterialKind::Mixture}},
                              what, "kind");
}

// The material's inputs (images or a program), the input its emission reads, its normal map.
void inputs_from(Material& m, const py::object& inputs, const py::object& program, int emission_input,
                 const py::object& normal_map, const std::string& what) {
  if (!inputs.is_none() && !program.is_none()) fail(what, "give inputs or a program, not both");
  m.program = program_from(program, what);
  add_image_inputs(m.program, inputs, what);
  if (!m.program.empty() && m.kind != MaterialKind::Mixture && m.kind != MaterialKind::Emission)
    fail(what, "inputs are for kinds 'mixture' and 'emission' only");
  if (emission_input < -1 || emission_input >= kMaxInputs) fail(what, "emission_input must be -1 (none) or an input index");
  m.emission_input = static_cast<int8_t>(emission_input);
  m.normal_map = normal_map_from(normal_map, what);
  if (m.normal_map.input >= 0 && m.kind != MaterialKind::Mixture) fail(what, "normal_map is for kind 'mixture' only");
}

uint32_t add_material(Scene& s, const std::string& name, const std::string& kind, const py::object& base_color,
                      int texture, double roughness, double ior, const py::object& specular_tint,
                      const py::object& emission, const py::object& lobes, double holdout, const py::object& inputs,
                      const py::object& normal_map, int emission_input, const py::object& program,
                      const py::object& replace) {
  const std::string what = "material '" + checked_name(name, "material") + "'";
  Material m;
  m.name = name;
  m.kind = material_kind(kind, what);
  m.base_color = color(base_color, what, "base_color");
  m.texture = texture;
  if (texture < -1) fail(what, "texture must be -1 (none) or a texture index");
  m.roughness = roughness;
  m.ior = ior;
  m.specular_tint = color(specular_tint, what, "specular_tint");
  m.emission = color(emission, what, "emission");
  inputs_from(m, inputs, program, emission_input, normal_map, what);
  lobes_from(lobes, m, what);
  if (holdout != 0.0 && m.kind != MaterialKind::Mixture) fail(what, "holdout is for kind 'mixture' only");
  if (!(holdout >= 0.0 && holdout <= 1.0)) fail(what, "holdout must be in [0, 1]");
  m.holdout = holdout;
  if (replace.is_none()) return s.add_material(std::move(m));
  const uint32_t index = replace.cast<uint32_t>();
  s.replace_material(index, std::move(m));
  return index;
}

}  // namespace

namespace ppm::python {

void bind_materials(SceneClass& c) {
  c.def("add_material", &add_material, py::arg("name"), py::arg("kind") = "diffuse",
        py::arg("base_color") = py::make_tuple(0.8, 0.8, 0.8), py::arg("texture") = -1, py::arg("roughness") = 0.0,
        py::arg("ior") = 1.45, py::arg("specular_tint") = py::make_tuple(1.0, 1.0, 1.0),
        py::arg("emission") = py::make_tuple(0.0, 0.0, 0.0), py::arg("lobes") = py::none(), py::arg("holdout") = 0.0,
        py::arg("inputs") = py::none(), py::arg("normal_map") = py::none(), py::arg("emission_input") = -1,
        py::arg("program") = py::none(), py::arg("replace") = py::none(),
        "Adds a material; returns its index (with `replace`, an index: that material becomes this one, "
        "and the surfaces using it keep the BVH; an emissive material cannot replace one a sphere or "
        "revolve uses). kind: diffuse, mirror, metal, glass, emission, holdout "
        "(a hole in the image: alpha 0 where camera rays reach it), mixture (`lobes`: a list of dicts "
        "with kind diffuse, translucent, transparent, conductor, glossy, dielectric, velvet, schlick_sheen "
        "or microfiber_sheen, weight, color, tint, "
        "roughness, ior, parts ('both', 'reflection', 'refraction'), layer (a dielectric reflection or a "
        "microfiber sheen that attenuates the lobes after it, as a Principled BSDF's specular layer, coat "
        "or sheen), textured (its colour times the material's `texture`), multiscatter (Cycles' "
        "Multiscatter GGX energy), beckmann (Beckmann's distribution rather than GGX), "
        "tint_f0 (a dielectric's tint scales F0 only, as the Principled BSDF's Specular Tint), and "
        "color_input, roughness_input (an input index, or (index, 'value' | 'sqrt')) and weight_inputs "
        "(up to 2 of (index, 'fraction' | 'complement')): parameters times a textured input), stretch "
        "((x, y): a conductor or glossy lobe's GGX alpha times x along the mesh's tangent, y across) and "
        "rotation (of the tangent about the normal, in turns), "
        "holdout (a mixture's Holdout weight: camera rays see that much of it as a hole in the alpha), "
        "and inputs (a mixture's: up to 8 of (texture index, 'rgb' | 'alpha' | 'grey'), looked up at the "
        "hit's UV; grey is the colour's Rec. 709 luminance) or program (a node program whose outputs are the "
        "inputs: see ppm_core.node_modes and engine/shading/node_program.h), and normal_map (a mixture's: "
        "dict(input=index, strength=1.0, space='tangent' | 'world' | 'direct', softening='conty_estevez' | "
        "'chiang' | 'none'), the input's colour c as the normal 2c - 1 in the tangent space of the mesh's "
        "tangents (add_mesh) or in world space, as Blender's Normal Map node, or (direct) the input itself as "
        "the normal; softening: Cycles' bump shadowing at the terminator, of "
        "Blender 4.3+ or of 3.x-4.2; valid_reflection=True: the normal turned so that the view's mirror "
        "direction stays above the surface, as Blender 3.x), and emission_input (an input whose value "
        "multiplies `emission`: a "
        "textured emission; a mixture's or an emission material's). "
        "emission is radiance in W/(m^2 sr) (Blender colour * strength).");
}

}  // namespace ppm::python
