// Hit points: what the eye pass records at the first non-specular surface of
// each eye path. Split by use: `HitPoint` is the compact record the photon
// gather reads (one cache line), `HitPointShading` the rest, read for direct
// light and glossy surfaces, and `HitPointStats` the progressive statistics
// (Hachisuka et al. 2008: radius r, photon count n, flux tau; plus m and
// tau_m, the photons gathered at the current radius not yet folded in).
#pragma once

#include "math/types.h"
#include "scene/scene.h"
#include "ppm/bounce_limits.h"
#include "base/fill_vector.h"
#include "ppm/light_components.h"

#include <vector>

namespace ppm {

struct HitPoint {
  Vec3 position;
  Vec3f normal;     // shading normal on the viewer's side
  uint32_t shading; // index into HitPointShading, for glossy evaluation
  double r2;        // current radius squared
  Vec3f weight;     // diffuse: eye-path throughput * albedo / pi; glossy: throughput
  uint32_t glossy;  // 1 if the BSDF must be evaluated per photon
};
static_assert(sizeof(HitPoint) == 64, "HitPoint should fill one cache line");

// Float where a BSDF needs no more; the geometric normal stays double, as ray offsets read its
// side at grazing angles.
struct HitPointShading {
  Vec3 geometric_normal;  // outward as the primitive defines it
  Vec3f shading_normal;
  Vec3f wo;               // towards the viewer
  Vec3f throughput;       // eye-path weight including 1/samples_per_pixel
  Vec2f uv;               // where the material's textures are looked up (Scene::surface_point)
  Vec3f smooth_normal;    // before a normal map (SurfacePoint::smooth_normal)
  glm::vec4 tangent;      // a mesh's tangent and bitangent sign (SurfacePoint::tangent)
  uint32_t material;
  uint32_t object;        // for its material's node program
  uint32_t primitive;     // ... and the mesh data it reads there
  uint32_t pixel;
  LightPath path;         // the ray that found it (the Light Path node)
};

// What Scene::surface_point needs to shade a hit point again.
inline SurfaceRecord surface_record(const HitPoint& h, const HitPointShading& sh) {
  return {h.position, sh.geometric_normal, Vec3(sh.shading_normal), Vec3(sh.wo), sh.uv, sh.smooth_normal, sh.tangent,
          sh.material, sh.object, sh.primitive, sh.path};
}

// Create as HitPointStats{} (all zero). No member initialisers: they would
// make resize() write every element on one thread (see fill_vector.h).
struct HitPointStats {
  double n;          // photons accumulated so far (alpha-weighted)
  uint32_t m;        // photons gathered at the current radius, not yet applied
  float pass_bias;   // the last pass's photons' bias sum, in luminance (error_estimate.h)
  Color tau;         // flux at the current radius (already times BSDF and throughput)
  Color tau_m;       // flux of the m pending photons
  Color direct;      // sum of direct-light samples
  float pass_flux;   // the last pass's photons' flux, in luminance (error_estimate.h)
  uint32_t sample;   // its pixel's eye sample it comes from (with EyePassOptions::record_samples)
};
static_assert(sizeof(HitPointStats) == 96, "HitPointStats grew");


// What a pixel's camera rays see directly, at no bounce (Cycles' Emit and Env passes): the
// emission of surfaces and lights, and the world.
struct SeenLight {
  Color emission{0.0};
  Color environment{0.0};
};

// A hit point in a medium (stochastic hit points): where an eye path's free path ended in a
// scattering event. It gathers volume photons in a sphere of radius r (the 3-D estimate,
// progressive.h) and samples the lights through the phase function. `weight` is the eye path's
// throughput times T / pdf of the distance drawn, without sigma_s: the volume photons' flux carries
// sigma_s, direct light multiplies it in.
struct VolumeHitPoint {
  Vec3 position;
  Vec3f weight;
  Vec3f direction;  // the eye path's propagation direction into the point
  float r2;
  uint32_t pixel;
  int32_t medium;
  MediumStack media;  // the shadow rays' start
  uint8_t route;      // its eye chain's (light_components.h: what it files its light as)
  Bounces chain;      // its eye chain's scatterings, with bounce limits (bounce_limits.h)
  bool beamed_elsewhere;  // its segment's VolumeBeam gathers the photon beams: it skips their photons
  // Found this pass: the gathered photons (flux times phase times weight) and the direct light;
  // the photons' bias sum in luminance (error_estimate.h's bias_sum_in_ball).
  uint32_t m;
  Vec3f tau;
  Vec3f direct;
  float pass_bias;
};

// An eye ray's segment through a homogeneous scattering medium (Settings::volume_beams): it
// gathers the pass's photon beams that pass within r of it (photon_pass_beams.cpp, the Beam x
// Beam estimate of Jarosz et al. 2011), the light that reached the medium along chains of
// specular bounces (photon_beams.h). Each such crossing lights the whole camera ray, where a
// point estimate needs its free path to end near a photon: in thin fog most never do. The hit
// point its free path draws (`point`) gathers the other volume photons. Beams gather only where
// the medium is optically thin at their radius (sigma_t r at most kThinBeam): in a dense one
// photon beams are short against r / sin(theta), the stretch over which two nearly parallel
// beams meet, and crossings cut by their ends go missing (a dense slab lit and seen from above
// 17% dark); there the hit point gathers every volume photon, those of beams too.
constexpr double kThinBeam = 0.1;
constexpr uint32_t kNoPoint = ~0u;
struct VolumeBeam {
  Vec3 origin;
  Vec3f direction;
  float length;
  Vec3f weight;   // the eye path's throughput at origin
  Vec3f sigma_t;  // the medium's extinction
  float r2;
  uint32_t pixel;
  int32_t medium;
  uint8_t route;  // as VolumeHitPoint's
  Bounces chain;
  uint32_t point;  // the segment's VolumeHitPoint in HitPoints::volume, or kNoPoint
  // Found this pass: photon beams, their flux (times transmittance, phase, sigma_s, 1 / sin and
  // weight) and bias sum (error_estimate.h's bias_sum_on_line), in luminance.
  uint32_t m;
  Vec3f tau;
  float pass_bias;
};

struct HitPoints {
  FillVector<HitPoint> points;
  FillVector<HitPointShading> shading;
  FillVector<HitPointStats> stats;
  std::vector<uint32_t> pixel_begin;  // hit points of pixel p: [pixel_begin[p], pixel_begin[p+1])
  std::vector<Color> emitted;         // per pixel: emission and background seen along eye paths
  std::vector<double> transparency;   // per pixel: the share of eye samples that leave it transparent
  std::vector<float> depth;           // per pixel: mean view-axis depth of the first hit (inf: none); optional
  // Optional, per pixel: Cycles' Denoising Albedo and Normal (world space), denoising_features.h.
  std::vector<Vec3f> albedo, feature_normal;
  // Optional, per pixel and eye sample: the luminance the sample saw directly (emission, background).
  std::vector<float> sample_light;
  std::vector<SeenLight> seen;  // optional, per pixel (EyePassOptions::record_seen)
  FillVector<Bounces> chain;          // with bounce limits: each eye chain's scatterings (bounce_limits.h)
  // Optional (EyePassOptions::record_components, light_components.h): per hit point its eye
  // chain's route and its share of the components; per pixel the components of the emission its
  // eye paths saw after a bounce, and its Color passes.
  std::vector<uint8_t> route;
  FillVector<HitPointComponents> components;
  std::vector<ComponentLight> pixel_components;
  // In scenes with media: each hit point's medium stack (its shadow rays start with it), and the
  // band's hit points in media, in pixel order.
  std::vector<MediumStack> media;
  std::vector<VolumeHitPoint> volume;
  std::vector<VolumeBeam> beams;  // with Settings::volume_beams, in pixel order
  size_t size() const { return points.size(); }
  size_t memory_bytes() const {
    return points.capacity() * sizeof(HitPoint) + shading.capacity() * sizeof(HitPointShading) +
           stats.capacity() * sizeof(HitPointStats) + chain.capacity() * sizeof(Bounces) + route.capacity() +
           components.capacity() * sizeof(HitPointComponents) + media.capacity() * sizeof(MediumStack) +
           volume.capacity() * sizeof(VolumeHitPoint) + beams.capacity() * sizeof(VolumeBeam) + pixel_bytes();
  }
  // Of which per pixel.
  size_t pixel_bytes() const {
    return pixel_begin.capacity() * sizeof(uint32_t) + emitted.capacity() * sizeof(Color) +
           transparency.capacity() * sizeof(double) + depth.capacity() * sizeof(float) +
           (albedo.capacity() + feature_normal.capacity()) * sizeof(Vec3f) + sample_light.capacity() * sizeof(float) +
           seen.capacity() * sizeof(SeenLight) + pixel_components.capacity() * sizeof(ComponentLight);
  }
};

}  // namespace ppm
