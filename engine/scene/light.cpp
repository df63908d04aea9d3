// Photon emission and direct-light sampling for each light kind (see light.h).
#include "scene/light.h"

#include "geometry/sphere.h"
#include "math/sampling.h"
#include "shading/scatter.h"

#include <stdexcept>

namespace ppm {
namespace {

double light_area(const Light& l) {
  // Scaled first: for sizes below ~1e-77 m the cross product's squared length underflows.
  const double su = max_abs(l.axis_u), sv = max_abs(l.axis_v);
  if (!(su > 0.0 && sv > 0.0)) return 0.0;
  const double a = 4.0 * su * sv * glm::length(glm::cross(l.axis_u / su, l.axis_v / sv));
  return l.kind == LightKind::Disk ? a * kPi / 4.0 : a;
}

Vec3 sample_area_point(const Light& l, double u1, double u2) {
  if (l.kind == LightKind::Disk) {
    const Vec2 d = sample_uniform_disk(u1, u2);
    return l.position + d.x * l.axis_u + d.y * l.axis_v;
  }
  return l.position + (2.0 * u1 - 1.0) * l.axis_u + (2.0 * u2 - 1.0) * l.axis_v;
}

double smoothstep01(double x) {
  x = glm::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// A point on the disk of radius R perpendicular to `dir` through the scene
// centre, moved back so rays start outside the scene bounds.
Vec3 scene_disk_origin(const Light& l, const Vec3& dir, double u1, double u2) {
  Vec3 t, b;
  make_basis(dir, t, b);
  const Vec2 d = sample_uniform_disk(u1, u2) * l.scene_radius;
  return l.scene_center - dir * (2.0 * l.scene_radius) + d.x * t + d.y * b;
}

// Soft falloff: a disk of the sphere's radius through its centre, facing p,
// with the sphere's radiance I / (pi r^2); on axis E = I / (d^2 + r^2) (Cycles).
bool sample_soft_sphere(const Light& l, const Vec3& p, double u1, double u2, DirectSample& out) {
  const Vec3 to_p = p - l.position;
  const double len = glm::length(to_p);
  if (!(len > 0.0)) return false;
  const Vec3 n = to_p / len;
  Vec3 t, b;
  make_basis(n, t, b);
  const Vec2 d = sample_uniform_disk(u1, u2) * l.radius;
  const Vec3 q = l.position + d.x * t + d.y * b;
  const Vec3 wi = q - p;
  const double dist2 = glm::dot(wi, wi);
  out.distance = std::sqrt(dist2);
  out.wi = wi / out.distance;
  const double cos_l = -glm::dot(out.wi, n);
  if (cos_l <= 0.0) return false;
  // radiance * cos_l * pi r^2 / dist2 with radiance = P / (4 pi^2 r^2), without
  // forming r^2: a tiny sphere must not turn into inf * 0.
  out.value = l.power * (cos_l / (4.0 * kPi * dist2));
  return true;
}

// A sphere light (or a spot's sphere): soft falloff (see sample_soft_sphere), or
// uniform over the cone the sphere subtends (pdf = 1 / solid angle).
bool sample_sphere(const Light& l, const Vec3& p, double u1, double u2, DirectSample& out) {
  if (l.soft_falloff) return sample_soft_sphere(l, p, u1, u2, out);
  const Vec3 d = l.position - p;
  const double dist2 = glm::dot(d, d), r2 = l.radius * l.radius;
  if (dist2 <= r2) return false;
  const double dist = std::sqrt(dist2);
  const double cos_max = std::sqrt(std::fmax(0.0, 1.0 - r2 / dist2));
  out.wi = to_world(sample_uniform_cone(u1, u2, cos_max), d / dist);
  double t;
  if (!intersect_sphere({l.position, l.radius}, {p, out.wi}, kInf, t)) t = dist;  // grazing the rim
  out.distance = t;
  // radiance * solid angle = P / (4 pi^2 r^2) * 2 pi (1 - cos_max), with
  // 1 - cos_max = (r^2/d^2) / (1 + cos_max): for a sphere far smaller than
  // its distance 1 - cos_max rounds to 0 and the light went black.
  out.value = l.power / (2.0 * kPi * dist2 * (1.0 + cos_max));
  return true;
}

// A spot light with a radius (Cycles 4.0+: a sphere light inside the spot's
// cone): the sphere's light, scaled by the spot's falloff along the sampled
// ray, as Cycles does (so the radius also softens the cone's edge).
bool sample_spot_sphere(const Light& l, const Vec3& p, double u1, double u2, DirectSample& out) {
  if (!sample_sphere(l, p, u1, u2, out)) return false;
  const double atten = spot_attenuation(l, -out.wi);
  out.value *= atten;
  return atten > 0.0;
}

// Cosine-weighted over the hemisphere of n: exact for a diffuse surface under a constant sky.
bool sample_uniform_background(const Light& l, const Vec3& n, double u1, double u2, DirectSample& out) {
  const Vec3 local = sample_cosine_hemisphere(u1, u2);
  if (local.z <= 0.0) return false;
  out.wi = to_world(local, n);
  out.distance = kInf;
  out.value = l.radiance * (kPi / local.z);
  return true;
}

// Direct light from an environment by two strategies, one sample each:
// cosine-weighted (`strategy` 0, good for a soft sky) and by the environment's
// density (1, good for a small sun), each weighted by the balance heuristic, so
// that the two samples' values add up to the estimate.
bool sample_environment(const Environment& env, const Vec3& n, double u1, double u2, int strategy,
                        DirectSample& out) {
  if (strategy == 0) {
    out.wi = to_world(sample_cosine_hemisphere(u1, u2), n);
  } else {
    double pdf;
    if (!env.sample(u1, u2, out.wi, pdf)) return false;
  }
  const double cos = glm::dot(out.wi, n);
  if (!(cos > 0.0)) return false;
  const double both = cos / kPi + env.pdf(out.wi);
  if (!(both > 0.0)) return false;
  out.distance = kInf;
  out.value = env.radiance(out.wi) / both;
  return true;
}

[[noreturn]] void fail(const std::string& what, const std::string& message) {
  throw std::invalid_argument(what + ": " + message);
}

}  // namespace

double spot_attenuation(const Light& l, const Vec3& dir_from_light) {
  const double c = glm::dot(dir_from_light, l.direction);
  if (c <= l.cos_half_spot) return 0.0;
  const double cosine = l.spot_cosine_falloff ? c : 1.0;
  if (l.spot_smooth <= 0.0) return cosine;
  return cosine * smoothstep01((c - l.cos_half_spot) / l.spot_smooth);
}

double spread_attenuation(const Light& l, double cos_a) {
  if (!(l.spread < kPi)) return 1.0;
  if (!(cos_a > 0.0)) return 0.0;
  const double h = 0.5 * l.spread, tan_h = std::tan(h);
  const double tan_a = std::sqrt(std::fmax(0.0, 1.0 - cos_a * cos_a)) / cos_a;
  // tan h - h loses its digits for small h: its series h^3/3 (Cycles switches at 0.05).
  const double normalization = h > 0.05 ? tan_h - h : h * h * h / 3.0;
  return std::fmax(tan_h - tan_a, 0.0) / normalization;
}

Light make_light(const LightSpec& spec) {
  const std::string what = "light '" + spec.name + "'";
  Light l;
  l.kind = spec.kind;
  l.name = spec.name;
  l.power = spec.power;
  l.visibility = spec.visibility;
  l.cast_shadow = spec.cast_shadow;
  l.spread = spec.spread;
  l.max_bounces = spec.max_bounces;
  Vec3 u(1, 0, 0), v(0, 1, 0);
  if (spec.has_matrix) {  // Blender's light matrix: emits along local -Z, size along local X and Y
    l.position = Vec3(spec.matrix[3]);
    l.direction = -Vec3(spec.matrix[2]);
    u = Vec3(spec.matrix[0]);
    v = Vec3(spec.matrix[1]);
  } else {
    l.position = spec.position;
    l.direction = spec.direction;
    Vec3 d;
    if (unit_direction(l.direction, d)) make_basis(d, u, v);
  }
  const double sx = spec.size_x, sy = spec.size_y;
  const bool has_size = spec.kind == LightKind::Rectangle || spec.kind == LightKind::Disk;
  if (has_size && !(sx > 0.0 && sy > 0.0 && std::isfinite(sx) && std::isfinite(sy))) fail(what, "size must be positive");
  l.axis_u = u * (0.5 * sx);
  l.axis_v = v * (0.5 * sy);
  l.radius = spec.radius;
  if (l.kind == LightKind::Point && spec.radius > 0.0) l.kind = LightKind::Sphere;  // Blender: a point with a radius
  if (!std::isfinite(spec.radius) || spec.radius < 0.0) fail(what, "radius must be >= 0");
  if (!(spec.spot_angle > 0.0 && spec.spot_angle <= 2.0 * kPi)) fail(what, "spot_angle must be in (0, 2*pi]");
  if (!(spec.spot_blend >= 0.0 && spec.spot_blend <= 1.0)) fail(what, "spot_blend must be in [0, 1]");
  if (!(spec.angle >= 0.0 && spec.angle <= kPi)) fail(what, "angle must be in [0, pi]");  // pi: a hemisphere, as in Blender
  l.cos_half_spot = std::cos(0.5 * spec.spot_angle);
  l.spot_smooth = (1.0 - l.cos_half_spot) * spec.spot_blend;
  l.cos_sun = std::cos(0.5 * spec.angle);
  l.spot_cosine_falloff = spec.spot_cosine_falloff;
  l.soft_falloff = spec.soft_falloff;
  return l;
}

bool light_is_delta(const Light& l) {
  return l.kind == LightKind::Point || (l.kind == LightKind::Spot && !(l.radius > 0.0)) ||
         (l.kind == LightKind::Sun && l.cos_sun >= 1.0);
}

void prepare_light(Light& l, const Aabb& bounds) {
  l.scene_center = bounds.empty() ? Vec3(0.0) : bounds.center();
  l.scene_radius = bounds.empty() ? 1.0 : std::fmax(0.5 * glm::length(bounds.extent()), 1e-12);
  switch (l.kind) {
    case LightKind::Point:
      l.flux = l.power;
      break;
    case LightKind::Sphere:
      l.flux = l.power;
      l.radiance = l.power / (4.0 * kPi * kPi * l.radius * l.radius);
      break;
    case LightKind::Spot: {
      // Integrate the falloff over the cone (it depends only on the angle).
      constexpr int kSteps = 2048;
      double integral = 0.0;
      for (int i = 0; i < kSteps; ++i) {
        const double c = l.cos_half_spot + (1.0 - l.cos_half_spot) * (i + 0.5) / kSteps;
        Light probe = l;
        probe.direction = Vec3(0, 0, 1);
        integral += spot_attenuation(probe, Vec3(std::sqrt(std::fmax(0.0, 1 - c * c)), 0.0, c));
      }
      l.spot_solid_angle = 2.0 * kPi * (1.0 - l.cos_half_spot) * integral / kSteps;
      l.flux = l.power / (4.0 * kPi) * l.spot_solid_angle;
      break;
    }
    case LightKind::Rectangle:
    case LightKind::Disk: {
      const double area = light_area(l);
      if (!(area > 0.0)) throw std::invalid_argument("light '" + l.name + "': area is zero");
      l.flux = l.power;
      l.radiance = l.power / (kPi * area);
      break;
    }
    case LightKind::Sun: {
      const double sin2 = 1.0 - l.cos_sun * l.cos_sun;
      l.radiance = sin2 > 0.0 ? l.power / (kPi * sin2) : Color(0.0);
      l.flux = l.power * kPi * l.scene_radius * l.scene_radius;
      break;
    }
    case LightKind::Background:
      // Flux through the scene's cross-section pi R^2 from all directions.
      l.radiance = l.power;
      l.flux = (l.environment != nullptr ? l.environment->integral() : l.power * (4.0 * kPi)) *
               (kPi * l.scene_radius * l.scene_radius);
      break;
    case LightKind::Triangle:
      l.flux = l.radiance * (2.0 * kPi * triangle_area(l.triangle));
      break;
    case LightKind::Medium:  // 4 pi L_e per unit volume, isotropic
      l.flux = l.power * (4.0 * kPi * l.volume);
      break;
  }
}

Color radiance_at(const Light& l, const Vec2& b) {
  if (l.program == nullptr) return l.radiance;
  ShadingContext at;
  const TrianglePrim& t = l.triangle;
  at.position = t.v0 + b.x * t.e1 + b.y * t.e2;
  at.normal = at.true_normal = at.incoming = triangle_normal(t);
  at.uv = (1.0 - b.x - b.y) * l.uvs[0] + b.x * l.uvs[1] + b.y * l.uvs[2];
  at.object = l.object;
  at.path.kind = 0;  // emission sampled at the light: no ray arrived (Cycles' PATH_RAY_EMISSION)
  std::array<Vec3f, kMaxInputs> values;
  l.program->run(at, *l.textures, values.data());
  return l.emission * Color(values[l.program_output]);
}

bool guidable(const Light& l) {
  // An area light of a narrower spread sends nothing into most of its hemisphere: drawn uniformly
  // there, its few photons inside would carry large weights.
  return l.kind == LightKind::Point || l.kind == LightKind::Sphere || (l.kind == LightKind::Spot && l.radius > 0.0) ||
         (emits_into_hemisphere(l) && !(l.spread < kPi));
}

PhotonEmission emit_photon_towards(const Light& l, const Vec3& d, double u1, double u2) {
  PhotonEmission e;
  e.flux = l.flux;
  switch (l.kind) {
    case LightKind::Point: e.ray = {l.position, d}; break;
    case LightKind::Sphere:
    case LightKind::Spot: {
      // The sphere's photons leave point n in direction d with density cos(n, d) / pi about d: its
      // own emission (uniform points, cosine directions) seen from the direction's side.
      const Vec3 n = to_world(sample_cosine_hemisphere(u1, u2), d);
      e.ray = {l.position + l.radius * n, d};
      e.rho2 = l.radius * l.radius * std::fmax(0.0, 1.0 - glm::dot(n, d) * glm::dot(n, d));
      if (l.kind == LightKind::Spot) e.flux = l.power * spot_attenuation(l, d);
      break;
    }
    case LightKind::Rectangle:
    case LightKind::Disk: {
      // Own density cos / pi against the uniform hemisphere's 1 / (2 pi).
      const double cos_d = std::max(0.0, glm::dot(d, l.direction));
      e.ray = {sample_area_point(l, u1, u2), d};
      e.flux = l.flux * (spread_attenuation(l, cos_d) * 2.0 * cos_d);
      break;
    }
    default: e.ray = {l.position, d}, e.flux = Color(0.0); break;
  }
  return e;
}

PhotonEmission emit_photon(const Light& l, double u1, double u2, double u3, double u4, double u5) {
  PhotonEmission e;
  e.flux = l.flux;
  switch (l.kind) {
    case LightKind::Point:
      e.ray = {l.position, sample_uniform_sphere(u1, u2)};
      break;
    case LightKind::Sphere: {
      const Vec3 n = sample_uniform_sphere(u1, u2);
      e.ray = {l.position + l.radius * n, to_world(sample_cosine_hemisphere(u3, u4), n)};
      const double cos_n = glm::dot(n, e.ray.direction);
      e.rho2 = l.radius * l.radius * std::fmax(0.0, 1.0 - cos_n * cos_n);
      break;
    }
    case LightKind::Spot: {
      // A direction in the cone, uniformly (the falloff weighs it): E[flux] = l.flux. A spot with a
      // radius is a sphere whose radiance the falloff of the direction alone masks, so its photons
      // in direction d leave uniformly from the sphere's outline seen along d (its front half).
      // Drawn from the whole sphere instead, a 7-degree spot wasted 999 photons in 1000 and gave
      // the rest 1000 times the flux: fog around it showed single photons as specks.
      const Vec3 d = to_world(sample_uniform_cone(u1, u2, l.cos_half_spot), l.direction);
      Vec3 origin = l.position;
      if (l.radius > 0.0) {
        const Vec2 q = sample_uniform_disk(u3, u4);
        origin += l.radius * to_world(Vec3(q, std::sqrt(std::fmax(0.0, 1.0 - glm::dot(q, q)))), d);
        e.rho2 = l.radius * l.radius * glm::dot(q, q);
      }
      e.ray = {origin, d};
      const double cone = 2.0 * kPi * (1.0 - l.cos_half_spot);
      e.flux = l.power / (4.0 * kPi) * spot_attenuation(l, d) * cone;
      break;
    }
    case LightKind::Rectangle:
    case LightKind::Disk: {
      // Cosine-weighted directions within the spread's half angle h, where its attenuation is not 0
      // (the cosine-weighted hemisphere's disk shrunk to radius sin h, of probability sin^2 h): the
      // attenuation's mean over the hemisphere is 1. A 30-degree softbox drew 15 of 16 photons
      // outside it.
      Vec3 local = sample_cosine_hemisphere(u3, u4);
      double inside = 1.0;
      if (l.spread < kPi) {
        const double s = std::sin(0.5 * l.spread), rho2 = s * s * (local.x * local.x + local.y * local.y);
        local = Vec3(s * local.x, s * local.y, std::sqrt(std::fmax(0.0, 1.0 - rho2)));
        inside = s * s;
      }
      e.ray = {sample_area_point(l, u1, u2), to_world(local, l.direction)};
      e.flux = l.flux * (spread_attenuation(l, local.z) * inside);
      break;
    }
    case LightKind::Sun: {
      const Vec3 d = to_world(sample_uniform_cone(u3, u4, l.cos_sun), l.direction);
      e.ray = {scene_disk_origin(l, d, u1, u2), d};
      break;
    }
    case LightKind::Background: {
      if (l.environment == nullptr) {
        const Vec3 d = sample_uniform_sphere(u3, u4);
        e.ray = {scene_disk_origin(l, d, u1, u2), d};
        break;
      }
      Vec3 from;  // the direction the light comes from; the photon travels the other way
      double pdf;
      if (!l.environment->sample(u3, u4, from, pdf)) {
        e.ray = {l.scene_center, Vec3(0.0, 0.0, 1.0)};
        e.flux = Color(0.0);
        break;
      }
      e.ray = {scene_disk_origin(l, -from, u1, u2), -from};
      e.flux = l.environment->radiance(from) * (kPi * l.scene_radius * l.scene_radius / pdf);
      break;
    }
    case LightKind::Triangle: {
      const Vec2 b = sample_uniform_triangle(u1, u2);
      const Vec3 p = l.triangle.v0 + b.x * l.triangle.e1 + b.y * l.triangle.e2;
      const Vec3 n = triangle_normal(l.triangle) * (u5 < 0.5 ? 1.0 : -1.0);
      e.ray = {p, to_world(sample_cosine_hemisphere(u3, u4), n)};
      if (l.program != nullptr) {  // positions drawn by area: each photon weighted by its point's share
        const Color here = radiance_at(l, b);
        for (int c = 0; c < 3; ++c) e.flux[c] = l.radiance[c] > 0.0 ? e.flux[c] * here[c] / l.radiance[c] : 0.0;
      }
      break;
    }
    case LightKind::Medium:  // a point inside a mesh needs the scene: photon_tracer_media.h draws it
      e.ray = {l.position, sample_uniform_sphere(u3, u4)};
      e.flux = Color(0.0);
      break;
  }
  return e;
}

int direct_samples(const Light& l) { return l.kind == LightKind::Background && l.environment != nullptr ? 2 : 1; }

bool sample_direct(const Light& l, const Vec3& p, const Vec3& n, double u1, double u2, DirectSample& out,
                   int strategy) {
  switch (l.kind) {
    case LightKind::Point:
    case LightKind::Spot: {
      if (l.kind == LightKind::Spot && l.radius > 0.0) return sample_spot_sphere(l, p, u1, u2, out);
      const Vec3 d = l.position - p;
      const double dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0)) return false;
      out.distance = std::sqrt(dist2);
      out.wi = d / out.distance;
      const double atten = l.kind == LightKind::Spot ? spot_attenuation(l, -out.wi) : 1.0;
      out.value = l.power * (atten / (4.0 * kPi * dist2));
      return atten > 0.0;
    }
    case LightKind::Sphere:
      return sample_sphere(l, p, u1, u2, out);
    case LightKind::Rectangle:
    case LightKind::Disk: {
      const Vec3 q = sample_area_point(l, u1, u2);
      const Vec3 d = q - p;
      const double dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0)) return false;
      out.distance = std::sqrt(dist2);
      out.wi = d / out.distance;
      const double cos_l = -glm::dot(out.wi, l.direction);
      if (cos_l <= 0.0) return false;
      out.value = l.radiance * (cos_l * light_area(l) / dist2 * spread_attenuation(l, cos_l));
      return true;
    }
    case LightKind::Sun:
      out.distance = kInf;
      if (l.cos_sun >= 1.0) {
        out.wi = -l.direction;
        out.value = l.power;  // irradiance on a surface facing the sun
      } else {
        out.wi = to_world(sample_uniform_cone(u1, u2, l.cos_sun), -l.direction);
        out.value = l.radiance * (2.0 * kPi * (1.0 - l.cos_sun));
      }
      return true;
    case LightKind::Background:
      return l.environment != nullptr ? sample_environment(*l.environment, n, u1, u2, strategy, out)
                                      : sample_uniform_background(l, n, u1, u2, out);
    case LightKind::Triangle: {
      const Vec2 b = sample_uniform_triangle(u1, u2);
      const Vec3 q = l.triangle.v0 + b.x * l.triangle.e1 + b.y * l.triangle.e2;
      const Vec3 d = q - p;
      const double dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0)) return false;
      out.distance = std::sqrt(dist2);
      out.wi = d / out.distance;
      const double cos_l = std::fabs(glm::dot(out.wi, triangle_normal(l.triangle)));
      out.value = radiance_at(l, b) * (cos_l * triangle_area(l.triangle) / dist2);
      return cos_l > 0.0;
    }
    case LightKind::Medium:  // not sampled: its photons carry its direct light
      return false;
  }
  return false;
}

Color light_seen(const Light& l, const Ray& ray, double tmax, double& t) {
  switch (l.kind) {
    case LightKind::Sphere:
      if (intersect_sphere({l.position, l.radius}, ray, tmax, t)) return l.radiance;
      return Color(0.0);
    case LightKind::Spot:
      if (l.radius > 0.0 && intersect_sphere({l.position, l.radius}, ray, tmax, t))
        return l.power * (spot_attenuation(l, -ray.direction) / (4.0 * kPi * kPi * l.radius * l.radius));
      return Color(0.0);
    case LightKind::Rectangle:
    case LightKind::Disk: {
      const double denom = glm::dot(ray.direction, l.direction);
      if (denom >= 0.0) return Color(0.0);  // seen from behind: one-sided
      t = glm::dot(l.position - ray.origin, l.direction) / denom;
      if (!(t > 0.0 && t < tmax)) return Color(0.0);
      const Vec3 q = ray.origin + t * ray.direction - l.position;
      const double a = glm::dot(q, l.axis_u) / glm::dot(l.axis_u, l.axis_u);
      const double b = glm::dot(q, l.axis_v) / glm::dot(l.axis_v, l.axis_v);
      const bool inside = l.kind == LightKind::Disk ? a * a + b * b <= 1.0
                                                    : std::fabs(a) <= 1.0 && std::fabs(b) <= 1.0;
      return inside ? l.radiance * spread_attenuation(l, -denom) : Color(0.0);
    }
    default:
      return Color(0.0);
  }
}

bool light_has_pdf(const Light& l) {
  switch (l.kind) {
    case LightKind::Sphere: return !l.soft_falloff;
    case LightKind::Spot: return l.radius > 0.0 && !l.soft_falloff;
    case LightKind::Rectangle:
    case LightKind::Disk: return light_area(l) > 0.0;
    case LightKind::Sun: return l.cos_sun < 1.0;
    case LightKind::Background: return l.environment != nullptr;
    default: return false;
  }
}

bool sample_light_with_pdf(const Light& l, const Vec3& p, double u1, double u2, DirectSample& out) {
  if (l.kind != LightKind::Background) return sample_direct(l, p, Vec3(0.0, 0.0, 1.0), u1, u2, out);
  double pdf;
  if (!l.environment->sample(u1, u2, out.wi, pdf) || !(pdf > 0.0)) return false;
  out.distance = kInf;
  out.value = l.environment->radiance(out.wi) / pdf;
  return true;
}

double light_pdf(const Light& l, const Vec3& p, const Vec3& wi) {
  switch (l.kind) {
    case LightKind::Sphere:
    case LightKind::Spot: {  // uniform in the cone the sphere subtends
      const Vec3 d = l.position - p;
      const double dist2 = glm::dot(d, d), r2 = l.radius * l.radius;
      if (dist2 <= r2) return 0.0;
      const double cos_max = std::sqrt(std::fmax(0.0, 1.0 - r2 / dist2));
      if (glm::dot(wi, d) < cos_max * std::sqrt(dist2)) return 0.0;
      return (1.0 + cos_max) * dist2 / (2.0 * kPi * r2);  // 1 / (2 pi (1 - cos_max)), as sample_sphere
    }
    case LightKind::Rectangle:
    case LightKind::Disk: {  // uniform over the area: distance^2 / (cos area)
      const double cos_l = -glm::dot(wi, l.direction);
      if (cos_l <= 0.0) return 0.0;
      const double t = glm::dot(l.position - p, l.direction) / -cos_l;
      return t > 0.0 ? t * t / (cos_l * light_area(l)) : 0.0;
    }
    case LightKind::Sun:
      return -glm::dot(wi, l.direction) >= l.cos_sun ? 1.0 / (2.0 * kPi * (1.0 - l.cos_sun)) : 0.0;
    case LightKind::Background: return l.environment->pdf(wi);
    default: return 0.0;
  }
}

}  // namespace ppm
