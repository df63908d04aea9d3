// Python bindings of ppm::Scene: the builder calls and batch ray casting.
#include "python/convert.h"
#include "python/node_program_bindings.h"
#include "scene/ray_batch.h"
#include "scene/scene.h"

#include <glm/gtc/matrix_transform.hpp>
#include <pybind11/stl.h>

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

struct ParsedLobe {
  Lobe lobe;
  bool textured = false;  // its colour times the material's `texture` (an input added for it)
};

// One lobe of a mixture from a dict (the keys are listed in add_material's documentation).
ParsedLobe lobe_from(const py::handle& item, const std::string& what) {
  if (!py::isinstance<py::dict>(item)) fail(what, "each lobe must be a dict");
  const py::dict d = py::reinterpret_borrow<py::dict>(item);
  static const char* const kKeys[] = {"kind",         "weight",  "color",       "tint",
                                      "roughness",    "ior",     "parts",       "layer",
                                      "textured",     "multiscatter", "beckmann", "tint_f0", "color_input",
                                      "roughness_input", "weight_inputs", "stretch", "rotation"};
  for (const auto& [key, value] : d) {
    const std::string k = py::str(key);
    if (std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char* n) { return k == n; }) == std::end(kKeys))
      fail(what, "unknown lobe key '" + printable(k) + "'");
  }
  ParsedLobe parsed;
  Lobe& l = parsed.lobe;
  l.kind = choice<LobeKind>(d.contains("kind") ? py::str(d["kind"]) : py::str("diffuse"),
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
  if (d.contains("textured")) parsed.textured = py::cast<bool>(d["textured"]);
  if (d.contains("multiscatter")) l.multiscatter = py::cast<bool>(d["multiscatter"]);
  if (d.contains("beckmann")) l.beckmann = py::cast<bool>(d["beckmann"]);
  if (d.contains("tint_f0")) l.tint_f0 = py::cast<bool>(d["tint_f0"]);
  if (d.contains("color_input")) l.color_input = input_ref(d["color_input"], InputRef::Value, what, "color_input");
  if (d.contains("roughness_input"))
    l.roughness_input = input_ref(d["roughness_input"], InputRef::Value, what, "roughness_input");
  if (d.contains("weight_inputs")) {
    const py::sequence refs = py::reinterpret_borrow<py::sequence>(d["weight_inputs"]);
    if (refs.size() > l.weight_inputs.size()) fail(what, "a lobe takes at most 2 weight_inputs");
    for (size_t i = 0; i < refs.size(); ++i)
      l.weight_inputs[i] = input_ref(refs[i], InputRef::Fraction, what, "weight_inputs");
  }
  if (d.contains("stretch")) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(d["stretch"]);
    if (pair.size() != 2) fail(what, "a lobe's stretch is (along the tangent, across it)");
    l.stretch_x = py::cast<double>(pair[0]);
    l.stretch_y = py::cast<double>(pair[1]);
  }
  if (d.contains("rotation")) l.rotation = py::cast<double>(d["rotation"]);
  if (parsed.textured && l.color_input.used()) fail(what, "a lobe is either textured or has a color_input");
  return parsed;
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

uint32_t add_material(Scene& s, const std::string& name, const std::string& kind, const py::object& base_color,
                      int texture, double roughness, double ior, const py::object& specular_tint,
                      const py::object& emission, const py::object& lobes, double holdout, const py::object& inputs,
                      const py::object& normal_map, int emission_input, const py::object& program,
                      const py::object& replace) {
  const std::string what = "material '" + checked_name(name, "material") + "'";
  Material m;
  m.name = name;
  m.kind = choice<MaterialKind>(kind,
                                {{"diffuse", MaterialKind::Diffuse},
                                 {"mirror", MaterialKind::Mirror},
                                 {"metal", MaterialKind::Metal},
                                 {"glass", MaterialKind::Glass},
                                 {"emission", MaterialKind::Emission},
                                 {"holdout", MaterialKind::Holdout},
                                 {"mixture", MaterialKind::Mixture}},
                                what, "kind");
  m.base_color = color(base_color, what, "base_color");
  m.texture = texture;
  if (texture < -1) fail(what, "texture must be -1 (none) or a texture index");
  m.roughness = roughness;
  m.ior = ior;
  m.specular_tint = color(specular_tint, what, "specular_tint");
  m.emission = color(emission, what, "emission");
  if (!inputs.is_none() && !program.is_none()) fail(what, "give inputs or a program, not both");
  m.program = program_from(program, what);
  add_image_inputs(m.program, inputs, what);
  if (!m.program.empty() && m.kind != MaterialKind::Mixture && m.kind != MaterialKind::Emission)
    fail(what, "inputs are for kinds 'mixture' and 'emission' only");
  if (emission_input < -1 || emission_input >= kMaxInputs) fail(what, "emission_input must be -1 (none) or an input index");
  m.emission_input = static_cast<int8_t>(emission_input);
  m.normal_map = normal_map_from(normal_map, what);
  if (m.normal_map.input >= 0 && m.kind != MaterialKind::Mixture) fail(what, "normal_map is for kind 'mixture' only");
  if (!lobes.is_none()) {
    if (m.kind != MaterialKind::Mixture) fail(what, "lobes are for kind 'mixture' only");
    if (py::isinstance<py::str>(lobes) || !py::isinstance<py::iterable>(lobes)) fail(what, "lobes must be a list");
    int textured_input = -1;  // the input `textured` lobes share: the material's texture, in colour
    for (const py::handle item : lobes) {
      ParsedLobe parsed = lobe_from(item, what);
      if (parsed.textured && texture >= 0) {
        if (textured_input < 0) {
          textured_input = static_cast<int>(m.program.outputs.size());
          m.program.add_image_output(texture, TextureChannel::Rgb);
        }
        parsed.lobe.color_input.input = static_cast<int8_t>(std::min(textured_input, kMaxInputs));
      }
      m.lobes.push_back(parsed.lobe);
    }
  }
  if (holdout != 0.0 && m.kind != MaterialKind::Mixture) fail(what, "holdout is for kind 'mixture' only");
  if (!(holdout >= 0.0 && holdout <= 1.0)) fail(what, "holdout must be in [0, 1]");
  m.holdout = holdout;
  if (replace.is_none()) return s.add_material(std::move(m));
  const uint32_t index = replace.cast<uint32_t>();
  s.replace_material(index, std::move(m));
  return index;
}

const std::initializer_list<std::pair<const char*, uint8_t>> kRayKindNames = {
    {"camera", kCameraRay}, {"diffuse", kDiffuseRay}, {"glossy", kGlossyRay},
    {"transmission", kTransmissionRay}, {"shadow", kShadowRay}};

// The RayKinds an object or light is visible to: None (all), or names from kRayKindNames.
uint8_t visibility(const py::object& names, const std::string& what) {
  if (names.is_none()) return kAllRayKinds;
  if (py::isinstance<py::str>(names) || !py::isinstance<py::iterable>(names))
    fail(what, "visibility must be None or a list of ray kinds (camera, diffuse, glossy, transmission, shadow)");
  uint8_t mask = 0;
  for (const py::handle name : names) {
    if (!py::isinstance<py::str>(name)) fail(what, "visibility must name ray kinds as strings");
    mask |= choice<uint8_t>(py::cast<std::string>(name), kRayKindNames, what, "visibility");
  }
  return mask;
}

// Byte pixels are kept as bytes (a memoryview of a Blender ImBuf, or uint8
// numpy); anything else becomes float32 (no copy if it already is) and is
// converted to the storage. The conversion runs without the GIL.
uint32_t add_texture(Scene& s, const std::string& name, const py::object& pixels, const py::object& storage_name,
                     bool clear_unusable) {
  using ByteArray = py::array_t<uint8_t, py::array::c_style>;
  using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
  const std::string what = "texture '" + checked_name(name, "texture") + "'";
  const py::array raw = array_or_null<py::array>(pixels);
  // Shape first, before a copy to float32 of something that cannot be a texture.
  if (!raw) fail(what, "pixels must be an array of shape (H, W, 4) or (H, W, 3)");
  if (raw.ndim() != 3 || (raw.shape(2) != 4 && raw.shape(2) != 3))
    fail(what, "pixels must have shape (H, W, 4) or (H, W, 3)");
  if (raw.shape(0) < 1 || raw.shape(1) < 1) fail(what, "width and height must be positive");
  if (raw.shape(0) > (1 << 20) || raw.shape(1) > (1 << 20)) fail(what, "width and height must be at most 1048576 pixels");
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    fail(what, std::string("pixels must be real numbers, not dtype kind '") + kind + "'");
  const bool bytes = raw.dtype().is(py::dtype::of<uint8_t>());
  if (!storage_name.is_none() && !py::isinstance<py::str>(storage_name))
    fail(what, "storage must be 'srgb8', 'linear8' or 'half'");
  const TexelStorage storage =
      storage_name.is_none() ? (bytes ? TexelStorage::Srgb8 : TexelStorage::Half)
                             : choice<TexelStorage>(py::cast<std::string>(storage_name),
                                                    {{"srgb8", TexelStorage::Srgb8},
                                                     {"linear8", TexelStorage::Linear8},
                                                     {"half", TexelStorage::Half}},
                                                    what, "storage");
  if (bytes && storage == TexelStorage::Half) fail(what, "byte pixels are stored as bytes: storage 'srgb8' or 'linear8'");
  const int width = static_cast<int>(raw.shape(1)), height = static_cast<int>(raw.shape(0));
  const int channels = static_cast<int>(raw.shape(2));
  if (bytes) {
    const ByteArray a = ByteArray::ensure(raw);  // a copy only if not C-contiguous
    py::gil_scoped_release unlocked;
    return s.add_texture(name, Texture::from_bytes(width, height, channels, a.data(), storage), clear_unusable);
  }
  const FloatArray a = array_or_null<FloatArray>(raw);
  if (!a) fail(what, "pixels must be an array of numbers");
  py::gil_scoped_release unlocked;
  return s.add_texture(name, Texture::from_floats(width, height, channels, a.data(), storage), clear_unusable);
}

py::dict texture_info(const Scene& s, uint32_t index) {
  if (index >= s.textures().size()) throw py::index_error("texture index out of range");
  const Texture& t = s.textures()[index];
  const char* storage = t.storage() == TexelStorage::Half    ? "half"
                        : t.storage() == TexelStorage::Srgb8 ? "srgb8"
                                                             : "linear8";
  py::dict d;
  d["width"] = t.width(), d["height"] = t.height(), d["storage"] = storage, d["bytes"] = t.bytes();
  d["max_rgb"] = t.max_rgb(), d["not_finite_texels"] = t.not_finite_texels();
  d["negative_texels"] = t.negative_texels(), d["most_negative"] = t.most_negative();
  return d;
}

// Integers in [0, 2^32): integer and boolean arrays as they are; float (and
// object) arrays only if every entry is a whole number, so that 0.5 or NaN is
// an error rather than silently truncated to a valid index.
std::vector<uint32_t> index_list(const py::handle& obj, const std::string& what, const std::string& field) {
  using IntArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
  const py::array raw = py::array::ensure(obj);
  if (!raw) fail(what, field + " must be an array of integers");
  const char kind = raw.dtype().kind();
  std::vector<uint32_t> out(raw.size());
  if (kind == 'f' || kind == 'O') {
    const DoubleArray a = array_or_null<DoubleArray>(raw);
    if (!a) fail(what, field + " must be an array of integers");
    const double* p = a.data();
    for (size_t i = 0; i < out.size(); ++i) {
      if (!(p[i] == std::floor(p[i])))
        fail(what, field + " entry " + std::to_string(i) + " is not an integer");
      if (p[i] < 0.0 || p[i] > 4294967295.0) fail(what, field + " entry " + std::to_string(i) + " is out of range");
      out[i] = static_cast<uint32_t>(p[i]);
    }
    return out;
  }
  if (kind != 'i' && kind != 'u' && kind != 'b')
    fail(what, field + std::string(" must be an array of integers, not dtype kind '") + kind + "'");
  const IntArray a = array_or_null<IntArray>(raw);
  if (!a) fail(what, field + " must be an array of integers");
  const int64_t* p = a.data();
  const bool unsigned64 = kind == 'u' && raw.dtype().itemsize() == 8;  // >= 2^63 wrapped to negative
  for (size_t i = 0; i < out.size(); ++i) {
    if (p[i] < 0 || p[i] > 0xffffffffll)
      fail(what, field + " entry " + std::to_string(i) + " is out of range" +
                     (unsigned64 && p[i] < 0 ? " (above 2^63)" : ""));
    out[i] = static_cast<uint32_t>(p[i]);
  }
  return out;
}

MeshInput mesh_input(const std::string& name, const py::object& positions, const py::object& triangles,
                     const py::object& normals, const py::object& uvs, const py::object& materials,
                     uint32_t object_id, const py::object& visible_to, bool holdout, const py::object& tangents,
                     const py::object& colors) {
  const std::string what = "mesh '" + checked_name(name, "mesh") + "'";
  MeshInput m;
  m.name = name;
  m.object_id = object_id;
  m.visibility = visibility(visible_to, what) | (holdout ? kHoldoutFlag : 0);
  m.positions = vec3_list(positions, what, "positions");
  {
    const py::array t = py::array::ensure(triangles);
    if (!t || t.ndim() != 2 || t.shape(1) != 3) fail(what, "triangles must be an integer array of shape (T, 3)");
    m.triangles = index_list(t, what, "triangles");
  }
  const size_t nt = m.triangles.size() / 3;
  if (!normals.is_none()) {
    DoubleArray n = DoubleArray::ensure(normals);
    if (n && n.ndim() == 3 && n.shape(1) == 3 && n.shape(2) == 3) n = n.reshape({n.shape(0) * 3, py::ssize_t(3)});
    m.normals = vec3_list(n, what, "normals");
    if (m.normals.size() != m.positions.size() && m.normals.size() != 3 * nt)
      fail(what, "normals must have one row per vertex (V, 3) or per corner (T, 3, 3)");
  }
  if (!uvs.is_none()) {
    DoubleArray u = DoubleArray::ensure(uvs);
    if (u && u.ndim() == 3 && u.shape(1) == 3 && u.shape(2) == 2) u = u.reshape({u.shape(0) * 3, py::ssize_t(2)});
    m.uvs = vec2_list(u, what, "uvs");
    if (m.uvs.size() != m.positions.size() && m.uvs.size() != 3 * nt)
      fail(what, "uvs must have one row per vertex (V, 2) or per corner (T, 3, 2)");
  }
  if (!tangents.is_none()) {
    DoubleArray a = DoubleArray::ensure(tangents);
    if (a && a.ndim() == 3 && a.shape(1) == 3 && a.shape(2) == 4) a = a.reshape({a.shape(0) * 3, py::ssize_t(4)});
    if (!a || a.ndim() != 2 || a.shape(1) != 4)
      fail(what, "tangents must have one row per vertex (V, 4) or per corner (T, 3, 4)");
    auto r = a.unchecked<2>();
    for (py::ssize_t i = 0; i < r.shape(0); ++i) m.tangents.emplace_back(r(i, 0), r(i, 1), r(i, 2), r(i, 3));
  }
  if (!colors.is_none()) {
    DoubleArray a = DoubleArray::ensure(colors);
    if (a && a.ndim() == 3 && a.shape(1) == 3 && a.shape(2) == 4) a = a.reshape({a.shape(0) * 3, py::ssize_t(4)});
    if (!a || a.ndim() != 2 || a.shape(1) != 4)
      fail(what, "colors must have one row per vertex (V, 4) or per corner (T, 3, 4)");
    auto r = a.unchecked<2>();
    for (py::ssize_t i = 0; i < r.shape(0); ++i) m.colors.emplace_back(r(i, 0), r(i, 1), r(i, 2), r(i, 3));
  }
  m.materials = index_list(materials, what, "materials");
  return m;
}

// add_mesh and replace_mesh: the same arguments into a MeshInput for the scene's method.
template <void (Scene::*method)(MeshInput)>
void mesh_call(Scene& s, const std::string& name, const py::object& positions, const py::object& triangles,
               const py::object& normals, const py::object& uvs, const py::object& materials, uint32_t object_id,
               const py::object& visible_to, bool holdout, const py::object& tangents, const py::object& colors) {
  (s.*method)(mesh_input(name, positions, triangles, normals, uvs, materials, object_id, visible_to, holdout,
                         tangents, colors));
}

void add_light(Scene& s, const std::string& kind, const std::string& name, const py::object& power,
               const py::object& color_obj, const py::object& position, const py::object& direction,
               const py::object& matrix, const py::object& size, double radius, double spot_angle,
               double spot_blend, double angle, bool spot_cosine_falloff, bool soft_falloff,
               const py::object& visible_to, bool cast_shadow, double spread, int max_bounces) {
  const std::string what = "light '" + checked_name(name, "light") + "'";
  LightSpec spec;
  spec.name = name;
  spec.kind = choice<LightKind>(kind,
                                {{"point", LightKind::Point},
                                 {"sphere", LightKind::Sphere},
                                 {"spot", LightKind::Spot},
                                 {"rectangle", LightKind::Rectangle},
                                 {"disk", LightKind::Disk},
                                 {"sun", LightKind::Sun}},
                                what, "kind");
  spec.visibility = visibility(visible_to, what);
  spec.power = color(power, what, "power") * color(color_obj, what, "color");
  spec.has_matrix = !matrix.is_none();
  if (spec.has_matrix) spec.matrix = mat4(matrix, what, "matrix");
  if (!position.is_none()) spec.position = vec3(position, what, "position");
  if (!direction.is_none()) spec.direction = vec3(direction, what, "direction");
  if (!size.is_none()) {
    const DoubleArray a = numbers_or_null(size);
    if (!a || (a.size() != 1 && a.size() != 2)) fail(what, "size must be one number or (size_x, size_y)");
    spec.size_x = a.data()[0];
    spec.size_y = a.data()[a.size() - 1];
  }
  spec.radius = radius;
  spec.spot_angle = spot_angle;
  spec.spot_blend = spot_blend;
  spec.angle = angle;
  spec.spot_cosine_falloff = spot_cosine_falloff;
  spec.soft_falloff = soft_falloff;
  spec.cast_shadow = cast_shadow;
  spec.spread = spread;
  spec.max_bounces = max_bounces;
  s.add_light(make_light(spec));
}

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
  double* o = origins.mutable_data();
  double* d = directions.mutable_data();
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const Ray ray = cam.generate_ray(x + 0.5, y + 0.5);
      const size_t i = 3 * (static_cast<size_t>(y) * cam.width + x);
      for (int k = 0; k < 3; ++k) o[i + k] = ray.origin[k], d[i + k] = ray.direction[k];
    }
  return py::make_tuple(origins, directions);
}

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
  const double* op_in = o.data();
  const double* dp_in = d.data();
  for (size_t i = 0; i < n; ++i) {
    const Vec3 org(op_in[3 * i], op_in[3 * i + 1], op_in[3 * i + 2]);
    const Vec3 dir(dp_in[3 * i], dp_in[3 * i + 1], dp_in[3 * i + 2]);
    if (!is_finite(org)) fail("intersect", "origin " + std::to_string(i) + " is not finite");
    Vec3 unit_dir;
    if (!unit_direction(dir, unit_dir)) fail("intersect", "direction " + std::to_string(i) + " is zero or not finite");
  }
  s.build();
  py::array_t<double> t(n);
  py::array_t<double> normal({n, size_t(3)});
  py::array_t<int64_t> prim(n), object(n), material(n);
  double* tp = t.mutable_data();
  double* np_ = normal.mutable_data();
  int64_t* pp = prim.mutable_data();
  int64_t* op = object.mutable_data();
  int64_t* mp = material.mutable_data();
  {
    py::gil_scoped_release release;
    intersect_batch(
        s, n, threads,
        [&](size_t i) {
          Ray ray;
          unit_direction(Vec3(dp_in[3 * i], dp_in[3 * i + 1], dp_in[3 * i + 2]), ray.direction);  // checked above
          ray.origin = Vec3(op_in[3 * i], op_in[3 * i + 1], op_in[3 * i + 2]);
          ray.kind = kind;
          return ray;
        },
        [&](size_t i, const Hit& h) {
          const bool found = h.found();
          tp[i] = found ? h.t : kInf;
          np_[3 * i] = found ? h.geometric_normal.x : 0.0;
          np_[3 * i + 1] = found ? h.geometric_normal.y : 0.0;
          np_[3 * i + 2] = found ? h.geometric_normal.z : 0.0;
          pp[i] = found ? int64_t(h.primitive) : -1;  // (uint32_t : int would make -1 unsigned)
          op[i] = found ? int64_t(h.object) : -1;
          mp[i] = found ? int64_t(h.material) : -1;
        });
  }
  py::dict out;
  out["t"] = t;
  out["normal"] = normal;
  out["primitive"] = prim;
  out["object"] = object;
  out["material"] = material;
  return out;
}


glm::vec4 rgba(const double* p, const std::string& what, const std::string& field) {
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(p[k])) fail(what, field + " must be finite");
  return glm::vec4(float(p[0]), float(p[1]), float(p[2]), float(p[3]));
}

void set_object_info(Scene& s, uint32_t object, const py::object& object_to_world,
                     const py::object& texspace_location, const py::object& texspace_size, double random,
                     double pass_index, const py::object& color, const py::object& attributes) {
  const std::string what = "object " + std::to_string(object);
  ObjectInfo info;
  info.object_to_world = mat4(object_to_world, what, "matrix");
  info.location = Vec3(info.object_to_world[3]);
  // An object scaled to nothing along an axis (it renders, flat) has no inverse: its coordinates are
  // then measured from its origin along the world's axes.
  const double det = glm::determinant(info.object_to_world);
  info.world_to_object = std::fabs(det) > 0.0 && std::isfinite(det) ? glm::inverse(info.object_to_world)
                                                                    : glm::translate(Mat4(1.0), -info.location);
  const Vec3 location = vec3(texspace_location, what, "texspace_location");
  Vec3 size = vec3(texspace_size, what, "texspace_size");
  for (int k = 0; k < 3; ++k)
    if (size[k] == 0.0) size[k] = 1.0;  // as Blender makes a flat texture space's
  info.texspace_min = location - size;
  info.texspace_size = 2.0 * size;
  info.random = static_cast<float>(random);
  info.pass_index = static_cast<float>(pass_index);
  const DoubleArray c = array_or_null<DoubleArray>(color);
  if (!c || c.size() != 4) fail(what, "color must be 4 numbers (RGBA)");
  info.color = rgba(c.data(), what, "color");
  if (!attributes.is_none()) {
    const DoubleArray a = matrix(attributes, 4, what, "attributes");
    for (py::ssize_t i = 0; i < a.shape(0); ++i) info.attributes.push_back(rgba(a.data() + 4 * i, what, "attributes"));
  }
  s.set_object_info(object, info);
}

// Runs a node program at n points (tests and the add-on's constant folding): (n, outputs, 3).
py::array_t<float> run_program(const Scene& s, const py::object& program, const py::object& position,
                               const py::object& normal, const py::object& incoming, const py::object& uv,
                               const py::object& tangent, uint32_t object, double footprint,
                               const std::string& ray) {
  const std::string what = "run_program";
  LightPath path = kCameraPath;
  path.kind = choice<uint8_t>(ray, {{"camera", kCameraRay}, {"diffuse", kDiffuseRay}, {"glossy", kGlossyRay},
                                    {"transmission", kTransmissionRay}, {"shadow", kShadowRay}, {"emission", 0}},
                              what, "ray");
  path.depth = path.kind == kCameraRay || path.kind == 0 ? 0 : 1;
  NodeProgram p = program_from(program, what);
  p.validate(s.textures().size(), what);
  const std::vector<Vec3> positions = vec3_list(position, what, "position");
  const size_t n = positions.size();
  auto optional3 = [&](const py::object& v, const char* field, Vec3 fallback) {
    std::vector<Vec3> out = v.is_none() ? std::vector<Vec3>(n, fallback) : vec3_list(v, what, field);
    if (out.size() != n) fail(what, std::string(field) + " must have one row per position");
    return out;
  };
  const std::vector<Vec3> normals = optional3(normal, "normal", Vec3(0.0, 0.0, 1.0));
  const std::vector<Vec3> incomings = optional3(incoming, "incoming", Vec3(0.0, 0.0, 1.0));
  std::vector<Vec2> uvs = uv.is_none() ? std::vector<Vec2>(n, Vec2(0.0)) : vec2_list(uv, what, "uv");
  if (uvs.size() != n) fail(what, "uv must have one row per position");
  std::vector<double> tangents;  // x, y, z, bitangent sign per point
  if (!tangent.is_none()) {
    const DoubleArray t = matrix(tangent, 4, what, "tangent");
    if (static_cast<size_t>(t.shape(0)) != n) fail(what, "tangent must have one row per position");
    tangents.assign(t.data(), t.data() + 4 * n);
  }
  py::array_t<float> out({n, p.outputs.size(), size_t(3)});
  float* o = out.mutable_data();
  std::array<Vec3f, kMaxInputs> values;
  for (size_t i = 0; i < n; ++i) {
    ShadingContext c;
    c.position = positions[i];
    c.normal = c.true_normal = normals[i];
    c.incoming = incomings[i];
    c.backfacing = glm::dot(c.incoming, c.normal) < 0.0;
    c.uv = uvs[i];
    if (!tangents.empty()) {
      c.tangent = Vec3(tangents[4 * i], tangents[4 * i + 1], tangents[4 * i + 2]);
      c.tangent_sign = tangents[4 * i + 3];
    }
    c.object = &s.object_info(object);
    c.camera = s.has_camera() ? &s.camera() : nullptr;
    c.path = path;
    c.footprint = footprint;
    p.run(c, s.textures(), values.data());
    for (size_t k = 0; k < p.outputs.size(); ++k)
      for (int j = 0; j < 3; ++j) *o++ = values[k][j];
  }
  return out;
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A scene for the PPM core. World space: metres, Z up.")
      .def(py::init<>())
      .def("add_material", &add_material, py::arg("name"), py::arg("kind") = "diffuse",
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
           "emission is radiance in W/(m^2 sr) (Blender colour * strength).")
      .def("set_object_info", &set_object_info, py::arg("object"), py::arg("matrix"),
           py::arg("texspace_location") = py::make_tuple(0.0, 0.0, 0.0),
           py::arg("texspace_size") = py::make_tuple(1.0, 1.0, 1.0), py::arg("random") = 0.0,
           py::arg("pass_index") = 0.0, py::arg("color") = py::make_tuple(1.0, 1.0, 1.0, 1.0),
           py::arg("attributes") = py::none(),
           "What node programs know of object id `object` (add_mesh's object_id): its object-to-world matrix "
           "(Texture Coordinate's Object), its texture space (Blender's texspace_location and _size: Generated), "
           "Object Info's Random, Pass Index and Color (RGBA), and `attributes`: (n, 4) RGBA values the "
           "program's object_attribute coordinates read by slot (the instruction's data); finite numbers only.")
      .def("run_program", &run_program, py::arg("program"), py::arg("position"), py::arg("normal") = py::none(),
           py::arg("incoming") = py::none(), py::arg("uv") = py::none(), py::arg("tangent") = py::none(),
           py::arg("object") = 0, py::arg("footprint") = 0.0, py::arg("ray") = "camera",
           "Runs a node program (add_material's `program`) at points (their normals, the direction towards "
           "the viewer, UVs, and UV tangents with the bitangent sign, (n, 4); footprint: the world size of a "
           "pixel there, as a camera ray sees it; ray: the kind of ray that arrived, as the Light Path node "
           "reads it: camera, diffuse, glossy, transmission, shadow or emission): float32 (n, outputs, 3).")
      .def("add_texture", &add_texture, py::arg("name"), py::arg("pixels"), py::arg("storage") = py::none(),
           py::arg("clear_unusable") = false,
           "Adds an RGBA or RGB texture of shape (H, W, 4) or (H, W, 3), row 0 at the bottom; returns its "
           "index. storage: 'srgb8' (sRGB-encoded bytes; the default for uint8 pixels), 'linear8', or 'half' "
           "(linear half floats; the default for other pixels). Float pixels stored as bytes are quantized "
           "(round(v * 255)). A texel with a negative, NaN or Inf colour (or a NaN or Inf alpha) is an "
           "error; with clear_unusable=True a texel with NaN or Inf is stored black and negative colour "
           "channels as 0, counted in texture_info().")
      .def("texture_info", &texture_info, py::arg("index"),
           "width, height, storage, bytes, max_rgb, not_finite_texels, negative_texels and most_negative "
           "of texture `index`.")
      .def("add_mesh", &mesh_call<&Scene::add_mesh>, py::arg("name"), py::arg("positions"), py::arg("triangles"),
           py::arg("normals") = py::none(), py::arg("uvs") = py::none(), py::arg("materials") = 0,
           py::arg("object_id") = 0, py::arg("visibility") = py::none(), py::arg("holdout") = false,
           py::arg("tangents") = py::none(), py::arg("colors") = py::none(),
           "Adds a world-space triangle mesh. normals/uvs/tangents per vertex or per corner (T, 3, k); "
           "tangents (k = 4): the UV map's tangent and, in the 4th column, the bitangent's sign (for "
           "tangent-space normal maps); colors (k = 4): the attribute node programs read (Attribute and Color "
           "Attribute nodes). materials: one index or one per triangle. visibility: the ray kinds that see it "
           "('camera', 'diffuse', 'glossy', 'transmission', 'shadow'; None: all), as Cycles' ray visibility. "
           "holdout: a hole in the image (alpha 0) where camera rays reach it; other rays see it as it is.")
      .def("replace_mesh", &mesh_call<&Scene::replace_mesh>, py::arg("name"), py::arg("positions"),
           py::arg("triangles"), py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
           py::arg("materials") = 0, py::arg("object_id") = 0, py::arg("visibility") = py::none(),
           py::arg("holdout") = false, py::arg("tangents") = py::none(), py::arg("colors") = py::none(),
           "Object `object_id`'s triangles (it has no other primitives) become this mesh's, arguments as for "
           "add_mesh: moved, or reshaped with any number of triangles and attributes, in the place of the "
           "object's first triangle. In a built dynamic scene, a mesh moved or reshaped with as many triangles "
           "and the same attributes refits the object's BVH subtree at build(); any other builds that subtree "
           "again and keeps the other objects'. Elsewhere the BVH is built afresh. ValueError where it cannot, "
           "the scene unchanged (the caller then builds a new Scene).")
      .def("remove_object", &Scene::remove_object, py::arg("object_id"),
           "Removes every primitive of object `object_id` (meshes, spheres, revolves) and returns how many "
           "there were (0: none, the scene unchanged). In a built dynamic scene build() then drops the "
           "object's BVH subtree and keeps the other objects'.")
      .def_property_readonly("subtrees_built", &Scene::subtrees_built,
                             "How many objects' BVH subtrees the last build() of a dynamic scene built; the "
                             "others were kept (objects added or given other primitives are built, moved ones "
                             "refitted).")
      .def_property("dynamic", &Scene::dynamic, &Scene::set_dynamic,
                    "Build the BVH object by object (False by default), so that objects can be added, moved, "
                    "reshaped and removed in a built scene at the cost of their own subtrees (the viewport); a "
                    "whole-scene BVH traces faster where objects overlap.")
      .def_property(
          "geometry_layout",
          [](const Scene& s) {
            const GeometryLayout l = s.geometry_layout();
            return std::string(l == GeometryLayout::Auto ? "auto" : l == GeometryLayout::Copies ? "copies" : "compact");
          },
          [](Scene& s, const std::string& layout) {
            s.set_geometry_layout(choice<GeometryLayout>(
                layout, {{"auto", GeometryLayout::Auto}, {"copies", GeometryLayout::Copies}, {"compact", GeometryLayout::Compact}},
                "scene", "geometry_layout"));
          },
          "How the built scene keeps its triangles for ray tests: 'copies' (each triangle's corners copied beside "
          "the BVH, 96 bytes a triangle more, the fastest), 'compact' (only its mesh's shared vertices) or 'auto' "
          "(copies up to 4,000,000 triangles; the default). The hits are the same, bit for bit.")
      .def_property_readonly("triangles_copied", &Scene::triangles_copied,
                             "Whether the built scene keeps copies of its triangles (geometry_layout).")
      .def("add_sphere",
           [](Scene& s, const std::string& name, const py::object& center, double radius, uint32_t material,
              uint32_t object_id, const py::object& visible_to, bool holdout) {
             const std::string what = "sphere '" + checked_name(name, "sphere") + "'";
             s.add_sphere(name, vec3(center, what, "center"), radius, material, object_id,
                          visibility(visible_to, what) | (holdout ? kHoldoutFlag : 0));
           },
           py::arg("name"), py::arg("center"), py::arg("radius"), py::arg("material"), py::arg("object_id") = 0,
           py::arg("visibility") = py::none(), py::arg("holdout") = false,
           "Adds a sphere; visibility and holdout as for add_mesh.")
      .def(
          "add_bezier_revolve",
          [](Scene& s, const std::string& name, const py::object& points, const std::string& kind,
             const py::object& matrix, uint32_t material, uint32_t object_id, const py::object& visible_to,
             bool holdout) {
            const std::string what = "bezier revolve '" + checked_name(name, "bezier revolve") + "'";
            const bool chain = choice<bool>(kind, {{"single", false}, {"chain", true}}, what, "kind");
            const Mat4 m = matrix.is_none() ? Mat4(1.0) : mat4(matrix, what, "matrix");
            s.add_bezier_revolve(name, vec2_list(points, what, "points"), chain, m, material, object_id,
                                 visibility(visible_to, what) | (holdout ? kHoldoutFlag : 0));
          },
          py::arg("name"), py::arg("points"), py::arg("kind") = "single", py::arg("matrix") = py::none(),
          py::arg("material") = 0, py::arg("object_id") = 0, py::arg("visibility") = py::none(),
          py::arg("holdout") = false,
          "Adds a surface of revolution: profile points (radius, height) revolved about local Z. "
          "kind 'single' (one Bezier curve, degree 1-8) or 'chain' (cubic segments, 3k+1 points); "
          "visibility and holdout as for add_mesh.")
      .def("add_light", &add_light, py::arg("kind"), py::arg("name") = "light", py::arg("power") = 100.0,
           py::arg("color") = py::make_tuple(1.0, 1.0, 1.0), py::arg("position") = py::none(),
           py::arg("direction") = py::none(), py::arg("matrix") = py::none(), py::arg("size") = py::none(),
           py::arg("radius") = 0.0, py::arg("spot_angle") = kPi / 4.0, py::arg("spot_blend") = 0.15,
           py::arg("angle") = 0.0, py::arg("spot_cosine_falloff") = false, py::arg("soft_falloff") = false,
           py::arg("visibility") = py::none(), py::arg("cast_shadow") = true, py::arg("spread") = kPi,
           py::arg("max_bounces") = 1024,
           "Adds a light in Cycles units. point/sphere/spot: power in W (intensity P/(4 pi)); rectangle/disk: "
           "emitted flux in W; sun: irradiance in W/m^2. Orientation from `matrix` (Blender's: emits along "
           "local -Z) or from position/direction. radius: a point's or spot's sphere. spot_cosine_falloff: "
           "Cycles 3.x's extra cos factor on spots; soft_falloff: Cycles' sphere-light falloff "
           "I cos/(d^2 + r^2) for direct light. spread: a rectangle's or disk's spread angle in radians, as "
           "Cycles' (pi: Lambertian). visibility: the ray kinds that see a light with a surface when they "
           "reach it (as for add_mesh; Blender lights leave out 'camera'); cast_shadow: False lights through "
           "everything in the way. max_bounces: Cycles' per-light Max Bounces, the longest path (in "
           "scatterings) the light reaches; 1024 is no limit.")
      .def("remove_textures_from", &Scene::remove_textures_from, py::arg("count"),
           "Removes the textures from index `count` on (a world's, to be exported again); refused "
           "(ValueError) while a material uses one. The world is black until set again; a built scene keeps "
           "its BVH.")
      .def_property_readonly("texture_count", [](const Scene& s) { return s.textures().size(); },
                             "How many textures the scene holds.")
      .def("remove_lights", &Scene::remove_lights,
           "Removes every light add_light added; the world and emissive surfaces stay. A built scene keeps "
           "its BVH: replacing the lights of a large scene costs the lights alone.")
      .def("set_camera", &set_camera, py::arg("matrix"), py::arg("width"), py::arg("height"),
           py::arg("projection") = "perspective", py::arg("fov") = 0.8575560591178853, py::arg("ortho_scale") = 7.0,
           py::arg("sensor_fit") = "auto", py::arg("shift_x") = 0.0, py::arg("shift_y") = 0.0,
           py::arg("clip_start") = 1e-3, py::arg("clip_end") = kInf, py::arg("focus_distance") = 10.0,
           py::arg("aperture_radius") = 0.0, py::arg("focal_length") = 0.0, py::arg("frame") = py::none(),
           "Sets the camera: camera-to-world matrix (looks down local -Z), image size, field of view "
           "in radians across the fitted side. Depth of field: focus_distance and aperture_radius in "
           "metres, focal_length in metres (0: focus distance >> focal length). frame: (x, y, width, "
           "height) in pixels of the full frame this image is a window of (a render border), for "
           "Window coordinates.")
      .def(
          "set_background",
          [](Scene& s, const py::object& c, const py::object& visible_to, int max_bounces) {
            s.set_background(color(c, "background", "color"), visibility(visible_to, "background"), max_bounces);
          },
          py::arg("color"), py::arg("visibility") = py::none(), py::arg("max_bounces") = 1024,
          "Constant background radiance in W/(m^2 sr). visibility: the ray kinds that see it when they "
          "escape (as for add_mesh; its light on surfaces stays). max_bounces: as for add_light (the "
          "world's Max Bounces).")
      .def(
          "set_environment",
          [](Scene& s, uint32_t texture, const py::object& rotation, const py::object& strength,
             const std::string& projection, const py::object& visible_to, int max_bounces) {
            const Mat4 m = rotation.is_none() ? Mat4(1.0) : mat4(rotation, "environment", "world_to_texture");
            s.set_environment(texture, m, color(strength, "environment", "strength"),
                              choice<EnvironmentProjection>(projection,
                                                            {{"equirectangular", EnvironmentProjection::Equirectangular},
                                                             {"mirror_ball", EnvironmentProjection::MirrorBall}},
                                                            "environment", "projection"),
                              visibility(visible_to, "environment"), max_bounces);
          },
          py::arg("texture"), py::arg("world_to_texture") = py::none(), py::arg("strength") = py::make_tuple(1.0, 1.0, 1.0),
          py::arg("projection") = "equirectangular", py::arg("visibility") = py::none(), py::arg("max_bounces") = 1024,
          "The world as an image around the scene (Blender's Environment Texture): texture is an index "
          "from add_texture (linear radiance), looked up in the direction world_to_texture (a 4x4 "
          "rotation, the Mapping node's) gives, as Cycles maps 'equirectangular' or 'mirror_ball' "
          "images; times strength (RGB). Replaces set_background; visibility and max_bounces as there.")
      .def(
          "set_camera_background",
          [](Scene& s, uint32_t texture, const py::object& strength) {
            s.set_camera_background(texture, color(strength, "camera background", "strength"));
          },
          py::arg("texture"), py::arg("strength") = py::make_tuple(1.0, 1.0, 1.0),
          "What camera rays see where they leave the scene instead of the background (a world whose Light "
          "Path tells camera rays apart): an equirectangular image (add_texture's index) times strength; it "
          "lights nothing. set_background and set_environment clear it.")
      .def("build", &Scene::build, "Builds the BVH (done automatically by Renderer and intersect).")
      .def("camera_rays", &camera_rays,
           "The camera's primary rays through the pixel centres, bottom row first: (origins, directions), "
           "each (width * height, 3), as the renderer generates them (clip start included).")
      .def("intersect", &intersect, py::arg("origins"), py::arg("directions"), py::arg("threads") = 0,
           py::arg("ray_kind") = py::none(),
           "Casts rays: returns dict(t (inf on miss), normal (geometric), primitive, object, material (-1 on "
           "miss)). "
           "threads: 0 uses all hardware threads. ray_kind: 'camera', 'diffuse', ... to pass through "
           "what that kind of ray does not see (None: hit everything visible to any ray).")
      .def_property_readonly("primitive_count", [](Scene& s) { s.build(); return s.primitive_count(); })
      .def_property_readonly("light_count", [](Scene& s) { s.build(); return s.lights().size(); });
}
