// Python side of node programs: a program from its dict (what the add-on's compiler emits), the
// names of each operation's modes in the core's order, and running a program at given points
// (constant folding at export, and tests against Cycles).
#include "python/node_program_bindings.h"

#include "python/bindings.h"

#include "python/convert.h"
#include "shading/node_color.h"
#include "shading/node_math.h"
#include "shading/textures/noise.h"
#include "shading/textures/patterns.h"
#include "shading/textures/voronoi.h"

#include <pybind11/stl.h>

#include <algorithm>

namespace py = pybind11;

namespace ppm::py_convert {
namespace {

const std::vector<std::pair<const char*, NodeOp>>& op_names() {
  static const std::vector<std::pair<const char*, NodeOp>> names = {
      {"coord", NodeOp::Coord},           {"convert", NodeOp::Convert},
      {"math", NodeOp::Math},             {"vector_math", NodeOp::VectorMath},
      {"mix", NodeOp::Mix},               {"mix_vector", NodeOp::MixVector},
      {"table", NodeOp::Table},           {"map_range", NodeOp::MapRange},
      {"clamp", NodeOp::Clamp},           {"separate", NodeOp::Separate},
      {"combine", NodeOp::Combine},       {"invert", NodeOp::Invert},
      {"gamma", NodeOp::Gamma},           {"bright_contrast", NodeOp::BrightContrast},
      {"hue_saturation", NodeOp::HueSaturation}, {"mapping", NodeOp::Mapping},
      {"vector_rotate", NodeOp::VectorRotate},   {"image", NodeOp::Image},
      {"noise", NodeOp::Noise},           {"voronoi", NodeOp::Voronoi},
      {"white_noise", NodeOp::WhiteNoise}, {"checker", NodeOp::Checker},
      {"gradient", NodeOp::Gradient},     {"wave", NodeOp::Wave},
      {"brick", NodeOp::Brick},           {"magic", NodeOp::Magic},
      {"fresnel", NodeOp::Fresnel},       {"layer_weight", NodeOp::LayerWeight},
      {"bump_offset", NodeOp::BumpOffset}, {"bump", NodeOp::Bump},
      {"normal_map", NodeOp::NormalMap},  {"environment_uv", NodeOp::EnvironmentUv},
      {"vector_transform", NodeOp::VectorTransform}, {"transform", NodeOp::Transform},
      {"wavelength", NodeOp::Wavelength},
      {"blackbody", NodeOp::Blackbody},  {"gabor", NodeOp::Gabor},
      {"grid", NodeOp::Grid},
  };
  return names;
}

NodeOp op_from(const std::string& name, const std::string& what) {
  for (const auto& [n, op] : op_names())
    if (name == n) return op;
  fail(what, "unknown node program operation '" + printable(name) + "'");
}

template <class T>
T integer(const py::dict& d, const char* key, T lo, T hi, const std::string& what) {
  if (!d.contains(key)) return lo;
  const long long v = py::cast<long long>(d[key]);
  if (v < static_cast<long long>(lo) || v > static_cast<long long>(hi))
    fail(what, std::string("node program instruction ") + key + " " + std::to_string(v) + " is out of range");
  return static_cast<T>(v);
}

template <size_t N>
void registers(const py::dict& d, const char* key, std::array<uint16_t, N>& out, const std::string& what) {
  if (!d.contains(key)) return;
  const auto list = py::cast<std::vector<long long>>(d[key]);
  if (list.size() > N) fail(what, std::string("a node program instruction has at most ") + std::to_string(N) + " " + key);
  for (size_t i = 0; i < list.size(); ++i) {
    if (list[i] < 0 || list[i] >= kMaxRegisters) fail(what, "a node program register is out of range");
    out[i] = static_cast<uint16_t>(list[i]);
  }
}

NodeInstruction instruction_from(const py::handle& item, const std::string& what) {
  if (!py::isinstance<py::dict>(item)) fail(what, "each node program instruction must be a dict");
  const py::dict d = py::reinterpret_borrow<py::dict>(item);
  for (const auto& [key, value] : d) {
    const std::string k = py::str(key);
    if (k != "op" && k != "mode" && k != "flags" && k != "extra" && k != "in" && k != "out" && k != "data")
      fail(what, "unknown node program instruction key '" + printable(k) + "'");
  }
  if (!d.contains("op")) fail(what, "a node program instruction needs an op");
  NodeInstruction ins;
  ins.op = op_from(py::str(d["op"]), what);
  ins.mode = integer<uint8_t>(d, "mode", 0, 255, what);
  ins.flags = integer<uint8_t>(d, "flags", 0, 255, what);
  ins.extra = integer<uint8_t>(d, "extra", 0, 255, what);
  ins.data = integer<uint32_t>(d, "data", 0, 0xFFFFFFFFu, what);
  registers(d, "in", ins.in, what);
  registers(d, "out", ins.out, what);
  return ins;
}

}  // namespace

NodeProgram program_from(const py::handle& value, const std::string& what) {
  NodeProgram p;
  if (value.is_none()) return p;
  if (!py::isinstance<py::dict>(value)) fail(what, "program must be a dict (constants, code, data, outputs, registers)");
  const py::dict d = py::reinterpret_borrow<py::dict>(value);
  for (const auto& [key, item] : d) {
    const std::string k = py::str(key);
    if (k != "constants" && k != "code" && k != "data" && k != "outputs" && k != "registers")
      fail(what, "unknown program key '" + printable(k) + "'");
  }
  if (d.contains("constants") && py::len(d["constants"]) > 0)
    for (const Vec3& c : vec3_list(d["constants"], what, "program constants")) p.constants.push_back(Vec3f(c));
  if (d.contains("code"))
    for (const py::handle item : d["code"]) p.code.push_back(instruction_from(item, what));
  if (d.contains("data")) p.data = py::cast<std::vector<float>>(d["data"]);
  if (d.contains("outputs")) {
    for (long long reg : py::cast<std::vector<long long>>(d["outputs"])) {
      if (reg < 0 || reg >= kMaxRegisters) fail(what, "a program output names a register out of range");
      p.outputs.push_back(static_cast<uint16_t>(reg));
    }
  }
  p.registers = d.contains("registers") ? py::cast<int>(d["registers"]) : static_cast<int>(p.constants.size()) + 1;
  return p;
}

// Each operation's modes by name, in the core's order (what `mode` counts).
py::dict node_modes() {
  py::dict modes;
  modes["math"] = std::vector<std::string>{
      "add", "subtract", "multiply", "divide", "multiply_add", "power", "logarithm", "sqrt", "inverse_sqrt",
      "absolute", "exponent", "minimum", "maximum", "less_than", "greater_than", "sign", "compare", "smooth_min",
      "smooth_max", "round", "floor", "ceil", "trunc", "fract", "modulo", "floored_modulo", "wrap", "snap",
      "pingpong", "sine", "cosine", "tangent", "arcsine", "arccosine", "arctangent", "arctan2", "sinh", "cosh",
      "tanh", "radians", "degrees"};
  modes["vector_math"] = std::vector<std::string>{
      "add", "subtract", "multiply", "divide", "multiply_add", "cross_product", "project", "reflect", "refract",
      "faceforward", "dot_product", "distance", "length", "scale", "normalize", "snap", "floor", "ceil", "modulo",
      "floored_modulo", "wrap", "fraction", "absolute", "minimum", "maximum", "sine", "cosine", "tangent", "power",
      "sign"};
  modes["mix"] = std::vector<std::string>{
      "mix", "add", "multiply", "screen", "overlay", "subtract", "divide", "difference", "exclusion", "darken",
      "lighten", "dodge", "burn", "hue", "saturation", "value", "color", "soft_light", "linear_light"};
  modes["coord"] = std::vector<std::string>{
      "generated", "normal", "uv", "object", "camera", "window", "reflection", "position", "shading_normal",
      "true_normal", "incoming", "backfacing", "tangent", "object_location", "object_random", "object_index",
      "attribute", "attribute_alpha", "attribute_mean", "object_color", "object_alpha", "object_attribute",
      "object_attribute_alpha", "object_attribute_mean", "is_camera_ray", "is_shadow_ray", "is_diffuse_ray",
      "is_glossy_ray", "is_singular_ray", "is_reflection_ray", "is_transmission_ray", "ray_length", "ray_depth",
      "diffuse_depth", "glossy_depth", "transmission_depth"};
  modes["noise"] = std::vector<std::string>{"fbm", "multifractal", "hybrid_multifractal", "ridged_multifractal",
                                            "hetero_terrain"};
  modes["voronoi"] = std::vector<std::string>{"f1", "f2", "smooth_f1", "distance_to_edge", "n_sphere_radius"};
  modes["voronoi_metric"] = std::vector<std::string>{"euclidean", "manhattan", "chebychev", "minkowski"};
  modes["gradient"] = std::vector<std::string>{"linear", "quadratic", "easing", "diagonal", "radial",
                                               "quadratic_sphere", "spherical"};
  return modes;
}

}  // namespace ppm::py_convert

namespace ppm::python {

void bind_node_modes(py::module_& m) {
  m.def("node_modes", &py_convert::node_modes,
        "Each node program operation's modes by name, in the order the core numbers them.");
}

}  // namespace ppm::python
