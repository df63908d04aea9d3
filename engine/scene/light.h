// Light sources in Cycles' units, and the two things the renderer asks of
// them: emit a photon (proportional to power) and sample direct light at a
// point. Conventions (see ARCHITECTURE.md "Units"):
//   point, sphere, spot: `power` P in W; radiant intensity P/(4 pi) W/sr
//     (a spot keeps that intensity inside its cone, smoothed by `blend`);
//   rectangle, disk:     `power` is the emitted flux in W, radiance P/(pi A),
//     one-sided, along `direction`;
//   sun:                 `power` is irradiance in W/m^2 on a surface facing it;
//   background:          `power` is radiance in W/(m^2 sr) from every direction,
//                        or an Environment gives it direction by direction;
//   emissive triangles come from materials (radiance, both sides);
//   medium: the region of an emitting medium (Scene::medium_region), `power` its emission radiance
//     per metre L_e, emitting 4 pi L_e W per cubic metre in every direction (flux 4 pi L_e V). No
//     light sampling reaches it: its photons carry its direct light (photon_tracer_media.h draws
//     them, since a point inside a mesh needs the scene's rays).
#pragma once

#include "geometry/ray.h"
#include "geometry/triangle.h"
#include "math/aabb.h"
#include "scene/environment.h"
#include "scene/medium.h"
#include "shading/texture.h"
#include "shading/node_program.h"

#include <array>
#include <string>

namespace ppm {

enum class LightKind : uint8_t { Point, Sphere, Spot, Rectangle, Disk, Sun, Background, Triangle, Medium };

struct Light {
  LightKind kind = LightKind::Point;
  std::string name;
  Color power{0.0};     // see the file comment for the unit of each kind
  Vec3 position{0.0};
  Vec3 direction{0.0, 0.0, -1.0};  // spot axis, area normal (emitting side), sun travel direction
  Vec3 axis_u{0.0}, axis_v{0.0};   // rectangle/disk: half-size vectors in the light's plane
  double radius = 0.0;             // sphere; spot: > 0 makes it a sphere inside its cone (Cycles 4.0+)
  double cos_half_spot = -1.0;     // spot: cos of half the spot angle
  double spot_smooth = 0.0;        // spot: (1 - cos_half_spot) * blend
  double cos_sun = 1.0;            // sun: cos of half the angular diameter
  double spread = kPi;             // rectangle, disk: Cycles' spread angle (pi: a Lambertian emitter)
  // Cycles 3.x multiplies a spot's intensity by the cosine to its axis (4.0 dropped it).
  bool spot_cosine_falloff = false;
  // Cycles' soft falloff for sphere lights (the only behaviour before 4.0, the
  // default since): direct light as from a disk of the sphere's radius facing
  // the receiver, irradiance I cos / (d^2 + r^2) instead of I cos / d^2.
  bool soft_falloff = false;
  // Which rays see a light with a surface (sphere, rectangle, disk) when they
  // reach it (Cycles' ray visibility; Blender lights hide from the camera by
  // default), and whether its direct light is blocked by what is in the way.
  uint8_t visibility = kAllRayKinds;
  bool cast_shadow = true;
  // Cycles' Max Bounces of a light (and the world's): the light reaches only the paths that
  // continue from at most this many scatterings (bounce_limits.h). Cycles' default, 1024, is no limit.
  int max_bounces = 1024;
  // Background: an image around the scene, or (nullptr) `power` from every direction.
  const Environment* environment = nullptr;
  // Emissive triangle; with a textured emission, `emission` times output `program_output` of its
  // material's node program where a point of it is (radiance_at), `radiance` then its mean over the
  // triangle.
  TrianglePrim triangle{};
  uint32_t primitive = 0;
  const NodeProgram* program = nullptr;
  int program_output = 0;
  const std::vector<Texture>* textures = nullptr;
  const ObjectInfo* object = nullptr;
  std::array<Vec2, 3> uvs{};
  Color emission{0.0};
  // Medium: its region's index (Scene::medium_region) and the volume it encloses, m^3.
  uint32_t region = 0;
  double volume = 0.0;
  // The mesh media a light inside them is in (Scene::media_at; its photons start there): a lamp in
  // a fog box; an emitting medium's region: the media at a point inside it, its own on top. Empty
  // for suns and the world.
  MediumStack media;
  // The light reaches across a mesh medium's boundary (a soft box half inside a fog box): each
  // photon's stack is `media` carried from the light's centre to where it leaves (Scene::media_along).
  bool straddles_media = false;

  // Derived by `prepare_light` once the scene bounds are known.
  Color radiance{0.0};  // sphere, area, triangle, sun (per sr), background
  Color flux{0.0};      // total emitted flux, W
  Vec3 scene_center{0.0};
  double scene_radius = 0.0;
  double spot_solid_angle = 0.0;  // integral of the spot falloff over the sphere
};

// A light as Blender describes it, which make_light turns into the model
// above: what the bindings fill in from Python.
struct LightSpec {
  LightKind kind = LightKind::Point;  // Point, Sphere, Spot, Rectangle, Disk or Sun
  std::string name = "light";
  Color power{100.0};  // times the light's colour (see the file comment for the unit)
  // Blender's object matrix (emits along local -Z, size along local X and Y), or else position and direction.
  bool has_matrix = false;
  Mat4 matrix{1.0};
  Vec3 position{0.0};
  Vec3 direction{0.0, 0.0, -1.0};
  double size_x = 1.0, size_y = 1.0;  // rectangle, disk: full sizes along the light's axes
  double radius = 0.0;                // point, spot: a sphere of this radius (a point with one is a sphere light)
  double spot_angle = kPi / 4.0;      // full cone angle, radians
  double spot_blend = 0.15;
  double angle = 0.0;                 // sun: angular diameter, radians (pi: a hemisphere)
  bool spot_cosine_falloff = false;
  bool soft_falloff = false;
  uint8_t visibility = kAllRayKinds;
  bool cast_shadow = true;
  double spread = kPi;
  int max_bounces = 1024;
};

// Throws std::invalid_argument naming the light and the setting out of range
// (Scene::add_light checks the rest: coordinates, sizes, power).
Light make_light(const LightSpec& spec);

struct PhotonEmission {
  Ray ray;
  Color flux;  // flux carried by this sample, an unbiased estimate of the light's total
  // A sphere's (a sphere spot's) photon: its ray's squared distance from the centre, for the
  // soft falloff (photon_tracer.h: soft_falloff_reaches); -1 for other lights.
  double rho2 = -1.0;
};

struct DirectSample {
  Vec3 wi;
  double distance;  // kInf for lights at infinity
  Color value;      // radiance / pdf (solid angle); contribution = f * |cos| * value
};

// Fills the derived fields; throws std::invalid_argument for a light that cannot emit sensibly.
void prepare_light(Light& light, const Aabb& scene_bounds);

PhotonEmission emit_photon(const Light& light, double u1, double u2, double u3, double u4, double u5);

// Photon guiding (ppm/photon_guide.h): lights whose photons' directions can be drawn from elsewhere.
// Their emission is the same in every direction (point lights, sphere and spot lights of a radius:
// over the sphere) or a cosine lobe about their direction (area lights of the full spread: over
// its hemisphere).
bool guidable(const Light& light);
inline bool emits_into_hemisphere(const Light& light) {
  return light.kind == LightKind::Rectangle || light.kind == LightKind::Disk;
}
// A guidable light's photon leaving in direction `d` (unit; for an area light, on its front side),
// from a point drawn with (u1, u2) as the light's own emission draws it given d. Its flux is the
// light's emission in d over a uniform density of directions on the sphere or hemisphere: drawn
// from a density that is `ratio` times the uniform one, flux / ratio is unbiased.
PhotonEmission emit_photon_towards(const Light& light, const Vec3& d, double u1, double u2);

// An emissive triangle's radiance at barycentric coordinates (b1, b2) (its texture looked up there).
Color radiance_at(const Light& light, const Vec2& b);

// Direct light needs direct_samples(light) samples, strategy 0, 1, ...; their
// values add up to the estimate (an environment: one cosine-weighted sample and
// one by its own density, combined by multiple importance sampling).
int direct_samples(const Light& light);

// How far a shadow ray from p towards sample `ds` goes: short of the light's own surface (by twice
// the ray offset there), kInf for a light at infinity; not positive where nothing is left.
inline double shadow_distance(const Vec3& p, const DirectSample& ds, double offset_floor) {
  if (!(ds.distance < kInf)) return ds.distance;
  return ds.distance * (1.0 - 1e-9) - 2.0 * ray_offset(p + ds.wi * ds.distance, offset_floor);
}

// `n` is the receiving surface's normal on the side light is gathered from.
bool sample_direct(const Light& light, const Vec3& p, const Vec3& n, double u1, double u2,
                   DirectSample& out, int strategy = 0);

// Lights whose sampled directions have a density that light_pdf gives (spheres and spots of a
// radius without the soft falloff, rectangles and disks, suns of an angle, environment images), so
// that light sampling and BSDF sampling can share their directions (multiple importance sampling).
bool light_has_pdf(const Light& light);
// A light_has_pdf light sampled from p: by sample_direct, and an environment by its density alone.
bool sample_light_with_pdf(const Light& light, const Vec3& p, double u1, double u2, DirectSample& out);
// The density per solid angle of sample_light_with_pdf's direction wi from p (0 where it never draws it;
// a rectangle's or disk's wi taken to meet it).
double light_pdf(const Light& light, const Vec3& p, const Vec3& wi);

// Is the light delta in position and direction (direct light needs one sample only)?
bool light_is_delta(const Light& light);

// Radiance seen along a camera or specular ray that reaches a visible light
// (sphere, spot with a radius, rectangle, disk) nearer than tmax; zero otherwise.
Color light_seen(const Light& light, const Ray& ray, double tmax, double& t);

// Radiance of a background light arriving from unit direction `dir`.
inline Color background_radiance(const Light& light, const Vec3& dir) {
  return light.environment != nullptr ? light.environment->radiance(dir) : light.radiance;
}

// Cycles' area light spread (a soft box's grid): the factor on the radiance
// leaving at `cos_a` to the light's normal, max(tan h - tan a, 0) / (tan h - h)
// for the half angle h, normalised so that the power stays that of a
// Lambertian emitter; 1 for a spread of pi.
double spread_attenuation(const Light& light, double cos_a);

// Cycles' spot falloff: smoothstep over the blend region.
double spot_attenuation(const Light& light, const Vec3& dir_from_light);

}  // namespace ppm
