// Running a node program (see node_program.h).
#include "shading/node_program.h"

#include "math/sphere_maps.h"
#include "shading/node_color.h"
#include "shading/node_math.h"
#include "shading/textures/procedural.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace ppm {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kPiF = 3.14159265358979f;

using nodes::MathOp;
using nodes::MixBlend;
using nodes::VectorMathOp;

Vec3f point(const Mat4& m, const Vec3& p) { return Vec3f(Vec3(m * glm::dvec4(p, 1.0))); }

const ObjectInfo& object_of(const ShadingContext& c) {
  static const ObjectInfo kNone;
  return c.object != nullptr ? *c.object : kNone;
}

// Light Path's outputs, as Cycles sets its path flags: a refraction is a glossy transmission.
Vec3f light_path(CoordKind kind, const LightPath& p) {
  auto flag = [](bool b) { return Vec3f(b ? 1.0f : 0.0f); };
  switch (kind) {
    case CoordKind::IsCameraRay: return flag(p.kind == kCameraRay);
    case CoordKind::IsShadowRay: return flag(p.kind == kShadowRay);
    case CoordKind::IsDiffuseRay: return flag(p.kind == kDiffuseRay);
    case CoordKind::IsGlossyRay: return flag(p.kind == kGlossyRay || p.kind == kTransmissionRay);
    case CoordKind::IsSingularRay: return flag(p.singular);
    case CoordKind::IsReflectionRay: return flag(p.kind == kDiffuseRay || p.kind == kGlossyRay);
    case CoordKind::IsTransmissionRay: return flag(p.kind == kTransmissionRay);
    case CoordKind::RayLength: return Vec3f(p.length);
    case CoordKind::RayDepth: return Vec3f(float(p.depth));
    case CoordKind::DiffuseDepth: return Vec3f(float(p.diffuse));
    case CoordKind::GlossyDepth: return Vec3f(float(p.glossy));
    case CoordKind::TransmissionDepth: return Vec3f(float(p.transmission));
    default: return Vec3f(0.0f);
  }
}

glm::vec4 object_attribute(const ObjectInfo& o, uint32_t slot) {
  return slot < o.attributes.size() ? o.attributes[slot] : glm::vec4(0.0f);
}

const VoxelGrid* object_grid(const ObjectInfo& o, uint32_t slot) {
  return slot < o.grids.size() ? o.grids[slot].get() : nullptr;
}

// A Grid instruction's colour, fac and alpha (see NodeOp::Grid).
void grid_op(const NodeInstruction& ins, ShadingContext& c, Vec3f* r) {
  const VoxelGrid* grid = object_grid(object_of(c), ins.data);
  const glm::vec4 v = grid != nullptr ? grid->lookup(r[ins.in[0]], c.voxel_random != 0 ? &c.voxel_random : nullptr)
                                      : glm::vec4(ins.flags & 1 ? 1.0f : 0.0f);
  r[ins.out[0]] = Vec3f(v);
  r[ins.out[1]] = Vec3f((v.x + v.y + v.z) * (1.0f / 3.0f));
  r[ins.out[2]] = Vec3f(v.w);
}

// `slot`: an object attribute's (ObjectInfo::attributes).
Vec3f coordinate(CoordKind kind, const ShadingContext& c, uint32_t slot) {
  const ObjectInfo& o = object_of(c);
  switch (kind) {
    case CoordKind::Generated: {
      const Vec3 local = Vec3(o.world_to_object * glm::dvec4(c.position, 1.0));
      return Vec3f((local - o.texspace_min) / o.texspace_size);
    }
    case CoordKind::Normal:  // object space, through the inverse transpose as Cycles
      return nodes::safe_normalize(Vec3f(glm::transpose(glm::dmat3(o.object_to_world)) * c.normal));
    case CoordKind::Uv: return Vec3f(float(c.uv.x), float(c.uv.y), 0.0f);
    case CoordKind::Object: return point(o.world_to_object, c.position);
    case CoordKind::Camera: return c.camera != nullptr ? Vec3f(c.camera->camera_space(c.position)) : Vec3f(c.position);
    case CoordKind::Window:
      return c.camera != nullptr ? Vec3f(c.camera->window_coordinates(c.position)) : Vec3f(0.0f);
    case CoordKind::Reflection: return Vec3f(2.0 * glm::dot(c.normal, c.incoming) * c.normal - c.incoming);
    case CoordKind::Position: return Vec3f(c.position);
    case CoordKind::ShadingNormal: return Vec3f(c.normal);
    case CoordKind::TrueNormal: return Vec3f(c.true_normal);
    case CoordKind::Incoming: return Vec3f(c.incoming);
    case CoordKind::Backfacing: return Vec3f(c.backfacing ? 1.0f : 0.0f);
    case CoordKind::Tangent: return Vec3f(c.tangent);
    case CoordKind::ObjectLocation: return Vec3f(o.location);
    case CoordKind::ObjectRandom: return Vec3f(o.random);
    case CoordKind::ObjectIndex: return Vec3f(o.pass_index);
    case CoordKind::Attribute: return Vec3f(c.attribute);
    case CoordKind::AttributeAlpha: return Vec3f(c.attribute.w);
    case CoordKind::AttributeMean: return Vec3f((c.attribute.x + c.attribute.y + c.attribute.z) * (1.0f / 3.0f));
    case CoordKind::ObjectColor: return Vec3f(o.color);
    case CoordKind::ObjectAlpha: return Vec3f(o.color.w);
    case CoordKind::ObjectAttribute: return Vec3f(object_attribute(o, slot));
    case CoordKind::ObjectAttributeAlpha: return Vec3f(object_attribute(o, slot).w);
    case CoordKind::ObjectAttributeMean: {
      const glm::vec4 a = object_attribute(o, slot);
      return Vec3f((a.x + a.y + a.z) * (1.0f / 3.0f));
    }
    default: return light_path(kind, c.path);
  }
  return Vec3f(0.0f);
}

// Blender's Fresnel of a dielectric for cos(theta) and relative IOR eta (1 under total reflection).
float fresnel_dielectric_cos(float cosi, float eta) {
  const float c = std::fabs(cosi);
  float g = eta * eta - 1.0f + c * c;
  if (g <= 0.0f) return 1.0f;
  g = std::sqrt(g);
  const float a = (g - c) / (g + c), b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
  return 0.5f * a * a * (1.0f + b * b);
}

// Layer Weight's Facing output.
float facing(float blend, float cosi) {
  float f = std::fabs(cosi);
  if (blend != 0.5f) {
    blend = std::clamp(blend, 0.0f, 1.0f - 1e-5f);
    blend = blend < 0.5f ? 2.0f * blend : 0.5f / (1.0f - blend);
    f = std::pow(f, blend);
  }
  return 1.0f - f;
}

// A table of `size` colours over [0, 1] (a baked ColorRamp or curve), linearly interpolated
// (`interpolate`) or not, clamped at the ends.
Vec3f table_lookup(const float* table, int size, float t, bool interpolate, float* alpha) {
  t = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f) * float(size - 1);
  const int i = std::clamp(static_cast<int>(t), 0, size - 1);
  const float f = t - float(i);
  const float* a = table + 4 * i;
  glm::vec4 c(a[0], a[1], a[2], a[3]);
  if (interpolate && f > 0.0f && i + 1 < size) c = glm::mix(c, glm::vec4(a[4], a[5], a[6], a[7]), f);
  if (alpha != nullptr) *alpha = c.w;
  return Vec3f(c);
}

// A baked curve (RGB, Vector or Float Curves) at x: the table spans [lo, hi] (stored before it) and
// beyond it continues along its end segments, as Cycles extrapolates curves. Channel k.
float curve_lookup(const float* table, int size, float x, int k) {
  const float lo = table[-2], hi = table[-1];
  float t = hi > lo ? (x - lo) / (hi - lo) : 0.0f;
  if (!std::isfinite(t)) t = 0.0f;
  if (t < 0.0f) return table[k] + (table[k] - table[4 + k]) * (-t) * float(size - 1);
  if (t > 1.0f) {
    const float* last = table + 4 * (size - 1);
    return last[k] + (last[k] - last[k - 4]) * (t - 1.0f) * float(size - 1);
  }
  return table_lookup(table, size, t, true, nullptr)[k];
}

// Blender's Mapping node: types 0 point, 1 texture, 2 vector, 3 normal.
Vec3f mapping(int type, const Vec3f& v, const Vec3f& location, const Vec3f& rotation, const Vec3f& scale) {
  const glm::mat3 r = nodes::euler_to_matrix(rotation);
  auto safe_divide = [](const Vec3f& a, const Vec3f& b) {
    return Vec3f(nodes::safe_divide(a.x, b.x), nodes::safe_divide(a.y, b.y), nodes::safe_divide(a.z, b.z));
  };
  switch (type) {
    case 0: return r * (v * scale) + location;
    case 1: return safe_divide(glm::transpose(r) * (v - location), scale);
    case 2: return r * (v * scale);
    default: return nodes::safe_normalize(r * safe_divide(v, scale));
  }
}

// The two directions a Bump node reads its height along, as Cycles: its orthonormals of the true
// normal (make_orthonormals), each as long as the pixel footprint where a camera ray found the
// point (its ray differential); elsewhere a thousandth of the object's texture space, far below its
// detail yet far above float rounding. The height is read `filter_width` of a step away.
void bump_steps(const ShadingContext& c, Vec3& dx, Vec3& dy) {
  const Vec3& n = c.true_normal;
  Vec3 a = (n.x != n.y || n.x != n.z) ? Vec3(n.z - n.y, n.x - n.z, n.y - n.x) : Vec3(n.z - n.y, n.x + n.z, -n.y - n.x);
  if (!unit_direction(a, a)) a = Vec3(1.0, 0.0, 0.0);
  double step = c.footprint;
  if (!(step > 0.0)) {
    const ObjectInfo& o = object_of(c);
    step = 1e-3 * std::max(glm::length(Vec3(glm::dmat3(o.object_to_world) * o.texspace_size)), 1e-6);
  }
  dx = step * a;
  dy = step * glm::cross(n, a);
}

// Cycles' bump: the surface gradient of the height from the heights beside the point (read
// filter_width steps away), n = normalize(fw |det| N - distance sign(det) gradient), then blended
// with N by strength. Operands: strength, distance, height here, height along dx, along dy, N,
// filter width.
Vec3f bump(const Vec3f* r, const NodeInstruction& ins, const ShadingContext& c) {
  Vec3 dx, dy;
  bump_steps(c, dx, dy);
  const Vec3 n(r[ins.in[5]]);
  const double fw = std::max<double>(r[ins.in[6]].x, 1e-6);
  const Vec3 rx = glm::cross(dy, n), ry = glm::cross(n, dx);
  const double det = glm::dot(dx, rx);
  const double hc = r[ins.in[2]].x, hx = r[ins.in[3]].x, hy = r[ins.in[4]].x;
  const Vec3 surfgrad = (hx - hc) * rx + (hy - hc) * ry;
  double distance = r[ins.in[1]].x;
  if (ins.flags & 1) distance = -distance;
  const double strength = std::max<double>(r[ins.in[0]].x, 0.0);
  Vec3 out = fw * std::fabs(det) * n - distance * (det < 0.0 ? -1.0 : 1.0) * surfgrad;
  if (!unit_direction(out, out)) return Vec3f(n);
  if (!unit_direction(strength * out + (1.0 - strength) * n, out)) return Vec3f(n);
  return Vec3f(out);
}

// The mapped normal for interpolated normal n (object space: the inverse transpose of the object's
// transform), then N + (mapped - N) * strength, as Cycles: from Blender 4 (measured: 4.2, not 3.4)
// a tangent-space normal enters that blend unnormalised (a short colour vector tilts less at
// partial strength), unless `normalise_first`; the others normalised.
Vec3 mapped_normal(const Vec3& color, int space, double strength, bool normalise_first, const ShadingContext& c,
                   const Vec3& n) {
  Vec3 mapped;
  if (space == 0) {  // tangent space
    if (c.tangent == Vec3(0.0)) return n;
    const Vec3 b = c.tangent_sign * glm::cross(n, c.tangent);
    mapped = color.x * c.tangent + color.y * b + color.z * n;
    if (normalise_first && !unit_direction(mapped, mapped)) return n;
  } else {
    mapped = space == 1 ? glm::transpose(glm::dmat3(object_of(c).world_to_object)) * color : color;
    if (!unit_direction(mapped, mapped)) return n;
  }
  strength = std::max(strength, 0.0);
  if (strength != 1.0) mapped = n + (mapped - n) * strength;
  return unit_direction(mapped, mapped) ? mapped : n;
}

// Blender's Normal Map node. Tangent space is built on the primitive's side of the surface (as
// Cycles reads the interpolated normal); the result faces the viewer, as every normal nodes see.
Vec3f normal_map(const Vec3f* r, const NodeInstruction& ins, const ShadingContext& c) {
  const Vec3 color = 2.0 * Vec3(r[ins.in[1]]) - 1.0;
  const double side = c.backfacing ? -1.0 : 1.0;
  return Vec3f(side * mapped_normal(color, ins.mode, r[ins.in[0]].x, ins.flags & 1, c, side * c.normal));
}

// Blender's Sphere and Tube projections of a point in the unit box (Cycles' map_to_sphere/tube).
Vec2 map_to_sphere(const Vec3f& co) {
  const float l = glm::length(co);
  if (!(l > 0.0f)) return Vec2(0.0);
  const float u = (co.x == 0.0f && co.y == 0.0f) ? 0.0f : (1.0f - std::atan2(co.x, co.y) / kPiF) * 0.5f;
  return Vec2(u, 1.0f - std::acos(std::clamp(co.z / l, -1.0f, 1.0f)) / kPiF);
}

Vec2 map_to_tube(const Vec3f& co) {
  const float len = std::sqrt(co.x * co.x + co.y * co.y);
  if (!(len > 0.0f)) return Vec2(0.0);
  return Vec2((1.0f - std::atan2(co.x / len, co.y / len) / kPiF) * 0.5f, (co.z + 1.0f) * 0.5f);
}

// Box projection's weights of the three axis-aligned faces for object-space normal n, as Cycles
// blends them: a face alone near its axis, two or three faces blended within `blend` of the edges.
Vec3f box_weights(Vec3f n, float blend) {
  n = glm::abs(n);
  n /= (n.x + n.y + n.z);
  const float limit = 0.5f * (1.0f + blend);
  auto ramp = [&](float a, float b) { return std::clamp((a / (a + b) - 0.5f * (1.0f - blend)) / blend, 0.0f, 1.0f); };
  if (n.x > limit * (n.x + n.y) && n.x > limit * (n.x + n.z)) return Vec3f(1, 0, 0);
  if (n.y > limit * (n.x + n.y) && n.y > limit * (n.y + n.z)) return Vec3f(0, 1, 0);
  if (n.z > limit * (n.x + n.z) && n.z > limit * (n.y + n.z)) return Vec3f(0, 0, 1);
  if (!(blend > 0.0f)) return Vec3f(1, 0, 0);  // no face is valid: one side, as Cycles
  if (n.z < (1.0f - limit) * (n.y + n.x)) {
    const float w = ramp(n.x, n.y);
    return Vec3f(w, 1.0f - w, 0.0f);
  }
  if (n.x < (1.0f - limit) * (n.y + n.z)) {
    const float w = ramp(n.y, n.z);
    return Vec3f(0.0f, w, 1.0f - w);
  }
  if (n.y < (1.0f - limit) * (n.x + n.z)) {
    const float w = ramp(n.x, n.z);
    return Vec3f(w, 0.0f, 1.0f - w);
  }
  return ((2.0f - limit) * n + (limit - 1.0f)) / (2.0f * limit - 1.0f);
}

// The texture of the UDIM tile (u, v) lies in, Cycles' way: tile 1001 + 10 row + column, with the
// coordinates truncated (so -0.5 falls in the first column); (u, v) moved into the tile. `table`:
// the count, then (tile, texture) pairs. -1: no such tile.
int udim_texture(const float* table, float& u, float& v) {
  if (!(std::fabs(u) < 1e6f && std::fabs(v) < 1e6f)) return -1;
  const int tx = static_cast<int>(u), ty = static_cast<int>(v);
  if (tx < 0 || ty < 0 || tx >= 10) return -1;
  const int tile = 1001 + 10 * ty + tx, count = static_cast<int>(table[0]);
  for (int k = 0; k < count; ++k) {
    if (static_cast<int>(table[1 + 2 * k]) != tile) continue;
    u -= float(tx);
    v -= float(ty);
    return static_cast<int>(table[2 + 2 * k]);
  }
  return -1;
}

// The Image node's RGBA: data is the texture, or with flag 1 the offset of a UDIM table.
glm::dvec4 image(const NodeInstruction& ins, const Vec3f* r, const std::vector<Texture>& textures,
                 const std::vector<float>& data) {
  const Vec3f co = r[ins.in[0]];
  const auto interpolation = static_cast<TextureInterpolation>(ins.mode & 3);
  const auto extension = static_cast<TextureExtension>((ins.mode >> 2) & 3);
  auto at = [&](float u, float v) {
    int texture = static_cast<int>(ins.data);
    if ((ins.flags & 1) && (texture = udim_texture(data.data() + ins.data, u, v)) < 0)
      return glm::dvec4(1.0, 0.0, 1.0, 1.0);  // Cycles' missing image
    return textures[texture].sample(Vec2(u, v), interpolation, extension);
  };
  switch (ins.extra) {
    case 1: {  // box: each face's image oriented so that none is mirrored, as Cycles maps them
      const Vec3f n = r[ins.in[1]];
      const Vec3f w = box_weights(n, r[ins.in[2]].x);
      glm::dvec4 c(0.0);
      if (w.x > 0.0f) c += double(w.x) * at(n.x < 0.0f ? 1.0f - co.y : co.y, co.z);
      if (w.y > 0.0f) c += double(w.y) * at(n.y > 0.0f ? 1.0f - co.x : co.x, co.z);
      if (w.z > 0.0f) c += double(w.z) * at(n.z > 0.0f ? 1.0f - co.y : co.y, co.x);
      return c;
    }
    case 2: {
      const Vec2 uv = map_to_sphere((co - 0.5f) * 2.0f);
      return at(float(uv.x), float(uv.y));
    }
    case 3: {
      const Vec2 uv = map_to_tube((co - 0.5f) * 2.0f);
      return at(float(uv.x), float(uv.y));
    }
    default: return at(co.x, co.y);
  }
}

// Blender's Wavelength node as Cycles computes it (export/wavelength.py): the colour matching
// functions interpolated (the index truncated towards zero, so 375-380 nm extrapolates the first
// step, as Cycles does), to scene linear, divided by 2.52, clamped at zero.
Vec3f wavelength(float nm, const float* data) {
  const float ii = (nm - 380.0f) * (1.0f / 5.0f);
  if (!(ii > -1.0f && ii < 80.0f)) return Vec3f(0.0f);
  const int i = static_cast<int>(ii);
  const float* c = data + 9 + 3 * i;
  const float t = ii - float(i);
  const Vec3f xyz = glm::mix(Vec3f(c[0], c[1], c[2]), Vec3f(c[3], c[4], c[5]), t);
  Vec3f rgb;
  for (int k = 0; k < 3; ++k) rgb[k] = data[3 * k] * xyz.x + data[3 * k + 1] * xyz.y + data[3 * k + 2] * xyz.z;
  return glm::max(rgb * (1.0f / 2.52f), Vec3f(0.0f));
}

// Blender's Blackbody node as Cycles evaluates it (export/blackbody.py): a piecewise fit in linear
// Rec.709 (R and G a/t + b t + c, B a cubic), its end colours held outside the fitted range, to
// scene linear, negative channels clamped.
Vec3f blackbody(float t, const float* data) {
  const float* fit = data + 9;
  const float *starts = fit, *ends = fit + 6, *held = fit + 8, *coefficients = fit + 14;
  Vec3f rec709;
  if (t >= ends[1]) {
    rec709 = Vec3f(held[3], held[4], held[5]);
  } else if (!(t >= ends[0])) {  // NaN too (Cycles would give NaN): the cold end keeps it finite
    rec709 = Vec3f(held[0], held[1], held[2]);
  } else {
    int i = 0;
    while (i < 6 && t >= starts[i]) ++i;
    const float* r = coefficients + 10 * i;
    const float *g = r + 3, *b = r + 6;
    rec709 = Vec3f(r[0] / t + r[1] * t + r[2], g[0] / t + g[1] * t + g[2], ((b[0] * t + b[1]) * t + b[2]) * t + b[3]);
  }
  Vec3f rgb;
  for (int k = 0; k < 3; ++k)
    rgb[k] = data[3 * k] * rec709.x + data[3 * k + 1] * rec709.y + data[3 * k + 2] * rec709.z;
  return glm::max(rgb, Vec3f(0.0f));
}

// Blender's Vector Transform between world, object and camera space; a normal moves as a
// direction and is normalised after, as Cycles does.
Vec3f vector_transform(const NodeInstruction& ins, const Vec3f& v, const ShadingContext& c) {
  const int from = ins.mode / 3, to = ins.mode % 3;
  const bool direction = ins.flags != 0;
  const ObjectInfo& o = object_of(c);
  Vec3 p(v);
  auto apply = [&](const Mat4& m) { p = Vec3(m * glm::dvec4(p, direction ? 0.0 : 1.0)); };
  Mat4 world_to_camera(1.0), camera_to_world(1.0);
  if (c.camera != nullptr) {
    camera_to_world = c.camera->camera_to_world * glm::dmat4(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1);
    world_to_camera = glm::inverse(camera_to_world);
  }
  if (from == 1 && to != 1) apply(o.object_to_world);
  if (from == 2 && to != 2) apply(camera_to_world);
  if (to == 1 && from != 1) apply(o.world_to_object);
  if (to == 2 && from != 2) apply(world_to_camera);
  return ins.flags == 2 ? nodes::safe_normalize(Vec3f(p)) : Vec3f(p);
}

}  // namespace

// The register arithmetic of the multi-line instructions: each reads its operands from `r` and
// writes its outputs there, as NodeProgram::step dispatches them.
namespace {

void convert_op(const NodeInstruction& ins, Vec3f* r) {
  const Vec3f v = r[ins.in[0]];
  const float grey = ins.mode == 0 ? nodes::rgb_to_grey(v)
                     : ins.mode == 2 ? nodes::rgb_to_grey_before_5(v) : (v.x + v.y + v.z) * (1.0f / 3.0f);
  r[ins.out[0]] = Vec3f(grey);
}

void math_op(const NodeInstruction& ins, Vec3f* r) {
  float v = nodes::math(static_cast<MathOp>(ins.mode), r[ins.in[0]].x, r[ins.in[1]].x, r[ins.in[2]].x);
  if (ins.flags & 1) v = std::clamp(v, 0.0f, 1.0f);
  r[ins.out[0]] = Vec3f(v);
}

void vector_math_op(const NodeInstruction& ins, Vec3f* r) {
  const auto& in = ins.in;
  const nodes::VectorResult v =
      nodes::vector_math(static_cast<VectorMathOp>(ins.mode), r[in[0]], r[in[1]], r[in[2]], r[in[3]].x);
  r[ins.out[0]] = v.vector;
  r[ins.out[1]] = Vec3f(v.value);
}

void mix_op(const NodeInstruction& ins, Vec3f* r) {
  float t = r[ins.in[0]].x;
  if (ins.flags & 1) t = std::clamp(t, 0.0f, 1.0f);
  Vec3f v = nodes::mix_blend(static_cast<MixBlend>(ins.mode), t, r[ins.in[1]], r[ins.in[2]]);
  if (ins.flags & 2) v = glm::clamp(v, 0.0f, 1.0f);
  r[ins.out[0]] = v;
}

void mix_vector_op(const NodeInstruction& ins, Vec3f* r) {
  Vec3f t = r[ins.in[0]];
  if (ins.flags & 1) t = glm::clamp(t, 0.0f, 1.0f);
  r[ins.out[0]] = glm::mix(r[ins.in[1]], r[ins.in[2]], t);
}

// A ColorRamp (mode 0: fac -> colour, alpha) or Curves (in fac, value; each channel through its
// curve, mode 1, or all through the first, mode 2).
void table_op(const NodeInstruction& ins, const float* table, Vec3f* r) {
  const int size = ins.extra + 2;
  if (ins.mode == 0) {
    float alpha = 1.0f;
    r[ins.out[0]] = table_lookup(table, size, r[ins.in[0]].x, ins.flags & 1, &alpha);
    r[ins.out[1]] = Vec3f(alpha);
    return;
  }
  const Vec3f v = r[ins.in[1]];
  Vec3f curved;
  for (int k = 0; k < 3; ++k) curved[k] = curve_lookup(table, size, v[k], ins.mode == 1 ? k : 0);
  r[ins.out[0]] = glm::mix(v, curved, r[ins.in[0]].x);
}

void map_range_op(const NodeInstruction& ins, Vec3f* r) {
  const auto& in = ins.in;
  if (ins.flags & 2) {  // vector: per component, each operand a vector
    Vec3f v;
    for (int k = 0; k < 3; ++k)
      v[k] = nodes::map_range(ins.mode, r[in[0]][k], r[in[1]][k], r[in[2]][k], r[in[3]][k], r[in[4]][k],
                              r[in[5]][k], ins.flags & 1);
    r[ins.out[0]] = v;
  } else {
    r[ins.out[0]] = Vec3f(nodes::map_range(ins.mode, r[in[0]].x, r[in[1]].x, r[in[2]].x, r[in[3]].x, r[in[4]].x,
                                           r[in[5]].x, ins.flags & 1));
  }
}

void clamp_op(const NodeInstruction& ins, Vec3f* r) {  // mode 0: min-max; 1: range (the bounds in either order)
  float lo = r[ins.in[1]].x, hi = r[ins.in[2]].x;
  if (ins.mode == 1 && lo > hi) std::swap(lo, hi);
  r[ins.out[0]] = Vec3f(std::min(std::max(r[ins.in[0]].x, lo), hi));
}

void separate_op(const NodeInstruction& ins, Vec3f* r) {
  const Vec3f c = r[ins.in[0]];
  const Vec3f v = ins.mode < 3 ? c : ins.mode < 6 ? nodes::rgb_to_hsv(c) : nodes::rgb_to_hsl(c);
  r[ins.out[0]] = Vec3f(v[ins.mode % 3]);
}

void combine_op(const NodeInstruction& ins, Vec3f* r) {
  const Vec3f v(r[ins.in[0]].x, r[ins.in[1]].x, r[ins.in[2]].x);
  r[ins.out[0]] = ins.mode == 1 ? nodes::hsv_to_rgb(v) : ins.mode == 2 ? nodes::hsl_to_rgb(v) : v;
}

void fresnel_op(const NodeInstruction& ins, const ShadingContext& at, Vec3f* r) {
  const float eta = std::max(r[ins.in[0]].x, 1e-5f);
  const float cosi = float(glm::dot(at.incoming, Vec3(r[ins.in[1]])));
  r[ins.out[0]] = Vec3f(fresnel_dielectric_cos(cosi, at.backfacing ? 1.0f / eta : eta));
}

void layer_weight_op(const NodeInstruction& ins, const ShadingContext& at, Vec3f* r) {
  const float blend = r[ins.in[0]].x;
  const float cosi = float(glm::dot(at.incoming, Vec3(r[ins.in[1]])));
  const float eta = std::max(1.0f - blend, 1e-5f);
  r[ins.out[0]] = Vec3f(fresnel_dielectric_cos(cosi, at.backfacing ? eta : 1.0f / eta));
  r[ins.out[1]] = Vec3f(facing(blend, cosi));
}

// The shading point the next instructions see: the base one, or moved by a bump filter's step.
void bump_offset_op(const NodeInstruction& ins, const ShadingContext& base, const Vec3f* r, ShadingContext& at) {
  at = base;
  if (ins.mode == 0) return;
  Vec3 dx, dy;
  bump_steps(base, dx, dy);
  const Vec3 d = std::max<double>(r[ins.in[0]].x, 1e-6) * (ins.mode == 1 ? dx : dy);  // in[0]: filter width
  at.position = base.position + d;
  at.uv = base.uv + Vec2(glm::dot(base.du_dp, d), glm::dot(base.dv_dp, d));
}

void environment_uv_op(const NodeInstruction& ins, Vec3f* r) {
  const Vec3 d(r[ins.in[0]]);
  const Vec2 uv = ins.mode == 0 ? equirectangular_uv(d) : mirror_ball_uv(d);
  r[ins.out[0]] = Vec3f(float(uv.x), float(uv.y), 0.0f);
}

void transform_op(const NodeInstruction& ins, const float* m, Vec3f* r) {
  const Vec3f v = r[ins.in[0]];
  const float w = ins.mode == 0 ? 1.0f : 0.0f;
  for (int k = 0; k < 3; ++k)
    r[ins.out[0]][k] = m[4 * k] * v.x + m[4 * k + 1] * v.y + m[4 * k + 2] * v.z + m[4 * k + 3] * w;
}

}  // namespace

void NodeProgram::step(const NodeInstruction& ins, ShadingContext& at, const ShadingContext& base,
                       const std::vector<Texture>& textures, Vec3f* r) const {
  const auto& in = ins.in;
  const auto& out = ins.out;
  auto f = [&](int k) { return r[in[k]].x; };
  auto operands = [&] { return data.data() + ins.data; };  // the instruction's constants
  switch (ins.op) {
    case NodeOp::Coord: r[out[0]] = coordinate(static_cast<CoordKind>(ins.mode), at, ins.data); break;
    case NodeOp::Convert: convert_op(ins, r); break;
    case NodeOp::Math: math_op(ins, r); break;
    case NodeOp::VectorMath: vector_math_op(ins, r); break;
    case NodeOp::Mix: mix_op(ins, r); break;
    case NodeOp::MixVector: mix_vector_op(ins, r); break;
    case NodeOp::Table: table_op(ins, operands(), r); break;
    case NodeOp::MapRange: map_range_op(ins, r); break;
    case NodeOp::Clamp: clamp_op(ins, r); break;
    case NodeOp::Separate: separate_op(ins, r); break;
    case NodeOp::Combine: combine_op(ins, r); break;
    case NodeOp::Invert: r[out[0]] = nodes::invert(f(0), r[in[1]]); break;
    case NodeOp::Gamma: r[out[0]] = nodes::gamma(r[in[0]], f(1)); break;
    case NodeOp::BrightContrast: r[out[0]] = nodes::bright_contrast(r[in[0]], f(1), f(2)); break;
    case NodeOp::HueSaturation: r[out[0]] = nodes::hue_saturation_value(f(0), f(1), f(2), f(3), r[in[4]]); break;
    case NodeOp::Mapping: r[out[0]] = mapping(ins.mode, r[in[0]], r[in[1]], r[in[2]], r[in[3]]); break;
    case NodeOp::VectorRotate:
      r[out[0]] = nodes::vector_rotate(ins.mode, ins.flags & 1, r[in[0]], r[in[1]], r[in[2]], f(3), r[in[4]]);
      break;
    case NodeOp::Image: {
      const glm::dvec4 c = image(ins, r, textures, data);
      r[out[0]] = Vec3f(c);
      r[out[1]] = Vec3f(float(c.w));
      break;
    }
    case NodeOp::Noise:
    case NodeOp::Voronoi:
    case NodeOp::WhiteNoise:
    case NodeOp::Checker:
    case NodeOp::Gradient:
    case NodeOp::Wave:
    case NodeOp::Brick:
    case NodeOp::Magic:
    case NodeOp::Gabor: textures::run(ins, data, r); break;
    case NodeOp::Fresnel: fresnel_op(ins, at, r); break;
    case NodeOp::LayerWeight: layer_weight_op(ins, at, r); break;
    case NodeOp::BumpOffset: bump_offset_op(ins, base, r, at); break;
    case NodeOp::Bump: r[out[0]] = bump(r, ins, base); break;
    case NodeOp::NormalMap: r[out[0]] = normal_map(r, ins, at); break;
    case NodeOp::EnvironmentUv: environment_uv_op(ins, r); break;
    case NodeOp::VectorTransform: r[out[0]] = vector_transform(ins, r[in[0]], at); break;
    case NodeOp::Wavelength: r[out[0]] = wavelength(f(0), operands()); break;
    case NodeOp::Blackbody: r[out[0]] = blackbody(f(0), operands()); break;
    case NodeOp::Transform: transform_op(ins, operands(), r); break;
    case NodeOp::Grid: grid_op(ins, at, r); break;
  }
}

void NodeProgram::run(const ShadingContext& ctx, const std::vector<Texture>& textures, Vec3f* results) const {
  std::array<Vec3f, kMaxRegisters> r;
  r[0] = Vec3f(0.0f);
  std::copy(constants.begin(), constants.end(), r.begin() + 1);
  ShadingContext at = ctx;
  for (const NodeInstruction& ins : code) step(ins, at, ctx, textures, r.data());
  for (size_t i = 0; i < outputs.size(); ++i) {
    Vec3f v = r[outputs[i]];
    // Nodes can overflow (Exponent of 1000) or make NaN (infinity times 0); a surface takes 0 there
    // rather than carry it into every photon that meets it.
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(v[k])) v[k] = 0.0f;
    if (i < output_max.size() && output_max[i] < kInfinity) v = glm::clamp(v, 0.0f, output_max[i]);
    results[i] = v;
  }
}

void NodeProgram::add_image_output(int texture, TextureChannel channel) {
  auto next = [this] { return static_cast<uint16_t>(registers++); };
  NodeInstruction uv;
  uv.op = NodeOp::Coord;
  uv.mode = static_cast<uint8_t>(CoordKind::Uv);
  uv.out[0] = next();
  NodeInstruction image;
  image.op = NodeOp::Image;
  image.in[0] = uv.out[0];
  image.out = {next(), next(), 0};
  image.data = static_cast<uint32_t>(std::max(texture, 0));
  code.push_back(uv);
  code.push_back(image);
  uint16_t result = channel == TextureChannel::Alpha ? image.out[1] : image.out[0];
  if (channel == TextureChannel::Grey) {
    NodeInstruction grey;
    grey.op = NodeOp::Convert;
    grey.in[0] = image.out[0];
    grey.out[0] = next();
    code.push_back(grey);
    result = grey.out[0];
  }
  outputs.push_back(result);
}

void NodeProgram::find_needs() {
  needs_ = {};
  for (const NodeInstruction& i : code) {
    needs_.uv_gradients |= i.op == NodeOp::BumpOffset;
    needs_.attribute |= i.op == NodeOp::Coord && i.mode >= static_cast<uint8_t>(CoordKind::Attribute) &&
                        i.mode <= static_cast<uint8_t>(CoordKind::AttributeMean);
  }
}

namespace {

bool valid_udim_table(const std::vector<float>& data, size_t at, size_t texture_count) {
  if (at >= data.size() || !(data[at] >= 1.0f && data[at] <= 100.0f)) return false;
  const size_t count = static_cast<size_t>(data[at]);
  if (at + 1 + 2 * count > data.size()) return false;
  for (size_t k = 0; k < count; ++k) {
    const float texture = data[at + 2 + 2 * k];
    if (!(texture >= 0.0f && texture < float(texture_count))) return false;
  }
  return true;
}

}  // namespace

void NodeProgram::validate(size_t texture_count, const std::string& what) const {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(what + ": node program: " + why); };
  if (registers > kMaxRegisters || registers < static_cast<int>(constants.size()) + 1)
    fail("it needs " + std::to_string(registers) + " registers (at most " + std::to_string(kMaxRegisters) + ")");
  for (const Vec3f& c : constants)
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) fail("a constant is not finite");
  for (size_t i = 0; i < code.size(); ++i) {
    const NodeInstruction& ins = code[i];
    const std::string at = "instruction " + std::to_string(i);
    for (uint16_t reg : ins.in)
      if (reg >= registers) fail(at + " reads register " + std::to_string(reg) + " beyond the program's");
    for (uint16_t reg : ins.out)
      if (reg >= registers || (reg >= 1 && reg <= constants.size()))
        fail(at + " writes register " + std::to_string(reg) + ", which is a constant or beyond the program's");
    if (static_cast<int>(ins.op) > static_cast<int>(NodeOp::Grid)) fail(at + " has an unknown operation");
    if (ins.op == NodeOp::Grid && (ins.flags > 1 || ins.data > 0xFFFF)) fail(at + " has an unknown flag or slot");
    if ((ins.op == NodeOp::Wavelength && size_t(ins.data) + 9 + 81 * 3 > data.size()) ||
        (ins.op == NodeOp::Blackbody && size_t(ins.data) + 9 + kBlackbodyFit > data.size()))
      fail(at + "'s table lies outside the data");
    if (ins.op == NodeOp::Transform && (ins.mode > 1 || size_t(ins.data) + 12 > data.size()))
      fail(at + "'s matrix lies outside the data");
    if (ins.op == NodeOp::Image && ins.extra > 3) fail(at + " has an unknown projection");
    if (ins.op == NodeOp::VectorTransform && (ins.mode > 8 || ins.flags > 2))
      fail(at + " has an unknown space or type");
    if (ins.op == NodeOp::Coord && ins.mode > static_cast<uint8_t>(CoordKind::TransmissionDepth))
      fail(at + " reads an unknown coordinate");
    if (ins.op == NodeOp::Image && !(ins.flags & 1) && ins.data >= texture_count)
      fail(at + " refers to a texture that does not exist");
    if (ins.op == NodeOp::Image && (ins.flags & 1) && !valid_udim_table(data, ins.data, texture_count))
      fail(at + "'s UDIM tiles lie outside the data or name textures that do not exist");
    if (ins.op == NodeOp::Table && (ins.mode > 2 || size_t(ins.data) + (size_t(ins.extra) + 2) * 4 > data.size() ||
                                    (ins.mode > 0 && ins.data < 2)))
      fail(at + "'s table lies outside the data");
    if (ins.op == NodeOp::Voronoi && ins.data >= 1 && ins.data <= constants.size())
      fail(at + " writes its W to a constant");
    if (!textures::valid(ins, data.size(), registers)) fail(at + " has an unknown mode or data");
  }
  if (outputs.size() > 8) fail("at most 8 outputs");
  for (uint16_t reg : outputs)
    if (reg >= registers) fail("an output names register " + std::to_string(reg) + " beyond the program's");
}

}  // namespace ppm

namespace ppm {
namespace {

// The largest magnitude an instruction's first output can take, from its operands' (inf: unknown).
// Coordinates of unit length (normals, directions, flags); the others are unbounded.
double coord_bound(CoordKind kind) {
  const bool unit = kind == CoordKind::Normal || kind == CoordKind::ShadingNormal || kind == CoordKind::TrueNormal ||
                    kind == CoordKind::Incoming || kind == CoordKind::Backfacing ||
                    kind == CoordKind::ObjectRandom || kind == CoordKind::Tangent || kind == CoordKind::Reflection ||
                    (kind >= CoordKind::IsCameraRay && kind <= CoordKind::IsTransmissionRay);
  return unit ? 1.0 : kInf;
}

// A Math node's bound from its operands' (a, b, c).
double math_bound(const NodeInstruction& ins, double a, double b, double c) {
  if (ins.flags & 1) return 1.0;
  switch (static_cast<nodes::MathOp>(ins.mode)) {
    case nodes::MathOp::Add:
    case nodes::MathOp::Subtract: return a + b;
    case nodes::MathOp::Multiply: return a * b;
    case nodes::MathOp::MultiplyAdd: return a * b + c;
    case nodes::MathOp::Minimum:
    case nodes::MathOp::Maximum: return std::max(a, b);
    case nodes::MathOp::Absolute: return a;
    case nodes::MathOp::Fraction:
    case nodes::MathOp::LessThan:
    case nodes::MathOp::GreaterThan:
    case nodes::MathOp::Compare:
    case nodes::MathOp::Sign:
    case nodes::MathOp::Sine:
    case nodes::MathOp::Cosine:
    case nodes::MathOp::Tanh: return 1.0;
    default: return kInf;
  }
}

// A Mix node's bound from its factor's and colours' (fac, a, c).
double mix_bound(const NodeInstruction& ins, double fac, double a, double c) {
  if (ins.flags & 2) return 1.0;
  const double t = (ins.flags & 1) ? 1.0 : fac;
  switch (static_cast<nodes::MixBlend>(ins.mode)) {
    case nodes::MixBlend::Mix:
    case nodes::MixBlend::Darken:
    case nodes::MixBlend::Lighten: return (ins.flags & 1) ? std::max(a, c) : kInf;
    case nodes::MixBlend::Add:
    case nodes::MixBlend::Subtract: return a + t * c;
    case nodes::MixBlend::Multiply: return a * std::max(1.0, t * c + 1.0);
    default: return kInf;
  }
}

// A ColorRamp's largest stop (curves extrapolate: unbounded).
double table_bound(const NodeInstruction& ins, const std::vector<float>& data) {
  if (ins.mode != 0) return kInf;
  double m = 0.0;
  for (int i = 0; i < (ins.extra + 2) * 4; ++i) m = std::max(m, double(std::fabs(data[ins.data + i])));
  return m;
}

// An image's brightest texel, or a tiled image's over its tiles and the missing tile's magenta.
double image_bound(const NodeInstruction& ins, const std::vector<Texture>& textures, const std::vector<float>& data) {
  if (!(ins.flags & 1)) return std::max(1.0, double(textures[ins.data].max_rgb()));
  double m = 1.0;
  for (int k = 0; k < static_cast<int>(data[ins.data]); ++k)
    m = std::max(m, double(textures[static_cast<size_t>(data[ins.data + 2 + 2 * k])].max_rgb()));
  return m;
}

// A Grid's colour and fac: its object's grid's largest value (1 or 0 where it has none).
double grid_bound(const NodeInstruction& ins, const ObjectInfo* object) {
  if (object == nullptr) return kInf;
  const VoxelGrid* grid = object_grid(*object, ins.data);
  return grid != nullptr ? std::max(0.0, double(grid->max_value())) : (ins.flags & 1 ? 1.0 : 0.0);
}

double bound_of(const NodeInstruction& ins, const std::vector<double>& b, const std::vector<Texture>& textures,
                const std::vector<float>& data, const ObjectInfo* object) {
  const double inf = kInf;
  auto in = [&](int k) { return b[ins.in[k]]; };
  switch (ins.op) {
    case NodeOp::Coord: return coord_bound(static_cast<CoordKind>(ins.mode));
    case NodeOp::Convert: return in(0);
    case NodeOp::Math: return math_bound(ins, in(0), in(1), in(2));
    case NodeOp::Mix: return mix_bound(ins, in(0), in(1), in(2));
    case NodeOp::MixVector: return std::max(in(1), in(2)) * (ins.flags & 1 ? 1.0 : inf);
    case NodeOp::Table: return table_bound(ins, data);
    case NodeOp::MapRange: return (ins.flags & 1) && ins.mode < 2 ? std::max(in(3), in(4)) : inf;
    case NodeOp::Clamp: return std::max(in(1), in(2));
    case NodeOp::Separate: return ins.mode < 3 ? in(0) : std::max(1.0, in(0));
    case NodeOp::Combine:  // HSL: l + (n - 1/2) chroma, |chroma| <= s (1 + |2 l - 1|)
      return ins.mode == 0 ? std::max({in(0), in(1), in(2)}) : ins.mode == 1 ? in(2) : in(2) + in(1) * (1.0 + in(2));
    case NodeOp::Invert: return 1.0 + in(1);
    case NodeOp::Image: return image_bound(ins, textures, data);
    case NodeOp::Grid: return grid_bound(ins, object);
    case NodeOp::Noise: return (ins.extra & 16) || ((ins.extra & 32) && ins.mode == 0) ? 1.0 : inf;
    case NodeOp::Voronoi: return inf;
    case NodeOp::WhiteNoise:
    case NodeOp::Gradient:
    case NodeOp::Wave:
    case NodeOp::Fresnel:
    case NodeOp::LayerWeight:
    case NodeOp::Bump:
    case NodeOp::NormalMap: return 1.0;
    case NodeOp::Checker: return std::max(in(1), in(2));
    case NodeOp::Brick: return std::max({in(1), in(2), in(3)});
    default: return inf;
  }
}

}  // namespace

double NodeProgram::output_bound(size_t i, const std::vector<Texture>& textures, const ObjectInfo* object,
                                 const Aabb* region) const {
  std::vector<double> b(static_cast<size_t>(std::max(registers, 1)), kInf);
  b[0] = 0.0;
  for (size_t k = 0; k < constants.size(); ++k) b[k + 1] = max_abs(Vec3(constants[k]));
  // Registers holding the Object (1) or Generated (2) coordinate, and the region's box in each.
  std::vector<uint8_t> coordinate(b.size(), 0);
  std::array<Aabb, 3> local{};
  if (region != nullptr && object != nullptr) {
    local[1] = transformed(*region, object->world_to_object);
    for (const Vec3& corner : {local[1].lo, local[1].hi})
      local[2].grow((corner - object->texspace_min) / object->texspace_size);
  }
  for (const NodeInstruction& ins : code) {
    double first = bound_of(ins, b, textures, data, object);
    const Aabb& box = local[coordinate[ins.in[0]]];
    if (ins.op == NodeOp::Grid && !box.empty())
      if (const VoxelGrid* grid = object_grid(*object, ins.data)) first = std::max(0.0, double(grid->max_in(box.lo, box.hi)));
    b[ins.out[0]] = first;
    for (uint16_t out : ins.out) coordinate[out] = 0;
    if (ins.op == NodeOp::Coord && static_cast<CoordKind>(ins.mode) == CoordKind::Object) coordinate[ins.out[0]] = 1;
    if (ins.op == NodeOp::Coord && static_cast<CoordKind>(ins.mode) == CoordKind::Generated) coordinate[ins.out[0]] = 2;
    // Second outputs: alphas, facings, fac of colour textures and the like stay within [0, 1] or
    // follow the first; colour-and-fac textures (Checker, Brick) give a fac in [0, 1].
    const bool unit_second = ins.op == NodeOp::Image || ins.op == NodeOp::LayerWeight || ins.op == NodeOp::Table ||
                             ins.op == NodeOp::Checker || ins.op == NodeOp::Brick || ins.op == NodeOp::Gradient ||
                             ins.op == NodeOp::Wave || ins.op == NodeOp::WhiteNoise;
    if (ins.out[1] != 0) b[ins.out[1]] = unit_second ? 1.0 : (ins.op == NodeOp::Noise ? first : kInf);
    if (ins.out[2] != 0) b[ins.out[2]] = kInf;
    if (ins.op == NodeOp::Grid) {  // fac: at most the colour's largest; alpha: the grid's alpha
      const VoxelGrid* grid = object != nullptr ? object_grid(*object, ins.data) : nullptr;
      if (ins.out[1] != 0) b[ins.out[1]] = first;
      if (ins.out[2] != 0) b[ins.out[2]] = grid != nullptr ? grid->max_alpha() : object != nullptr ? 1.0 : kInf;
    }
    if (ins.op == NodeOp::Voronoi && ins.data != 0) b[ins.data] = kInf, coordinate[ins.data] = 0;
    b[0] = kInf;  // scratch: whatever was written there last
  }
  const double limit = i < output_max.size() ? double(output_max[i]) : kInf;
  return std::min(b[outputs[i]], limit);
}

}  // namespace ppm
