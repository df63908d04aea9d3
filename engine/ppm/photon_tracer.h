// Photon paths: emitted from a light chosen by flux, scattered by the BSDFs
// with Russian roulette, deposited at every non-specular surface they reach
// (after the first bounce when direct light is sampled separately).
//
// In scenes whose BVH outgrows the caches (Scene::interleaves_walks), paths
// are traced a wave at a time: the next ray of every live path in the wave is
// cast together (Scene::intersect_many), so their BVH walks overlap each
// other's cache misses, then every path takes its bounce. A photon's random
// numbers and its path are the same as traced alone; only the order in which
// different photons deposit changes.
//
// With bounce limits (bounce_limits.h) a path counts its scatterings, hands the
// counts to each deposit, and ends once no hit point could take its photons.
#pragma once

#include "math/rng.h"
#include "ppm/bounce_limits.h"
#include "ppm/photon_guide.h"
#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

#include <cstdint>

namespace ppm {

// A photon between bounces: the ray it travels next and the flux it carries.
struct PhotonPath {
  Rng rng{0, 0, 0};
  Color flux;
  Ray ray;
  int bounce;
  Bounces used;  // scatterings after the first, plus the light's head start (bounce_limits.h)
  // Whether every scattering so far was specular (a delta lobe, or a surface photons pass without
  // depositing), and there was one: its deposits are caustics (light_components.h).
  bool specular_only = false;
  bool scattered = false;
  int32_t origin = -1;  // with guiding (photon_guide.h): slot * kBins + the bin it left in
  // From a sphere (or sphere spot) with Cycles' soft falloff: the light, and the squared distance
  // of the photon's first ray from its centre (soft_falloff_reaches).
  const Light* soft = nullptr;
  double soft_rho2 = 0.0;
  bool caustic() const { return scattered && specular_only; }
};

// Cycles' soft falloff (Light::soft_falloff): a receiver sees the sphere as the disk of its radius r
// facing it, which subtends less than the sphere does near it (atan(r / D) against asin(r / D) at D
// from the centre), with the sphere's radiance. So the sphere's photon along a ray rho from the
// centre reaches its first point x only if x sees that ray within the disk: rho^2 (D^2 + r^2) <=
// r^2 D^2; otherwise Cycles' light never arrives there that way. Far from the light nothing is lost.
// Measured: fog_caustic's spot of radius 1 m (soft falloff, Blender's default) read 3.7% above
// Cycles 5.0 with the whole sphere's photons, and 0.1% without the falloff in both engines.
inline bool soft_falloff_reaches(const PhotonPath& p, const Vec3& x) {
  if (p.soft == nullptr || p.bounce > 0) return true;
  const Vec3 to_x = x - p.soft->position;
  const double d2 = glm::dot(to_x, to_x), r2 = p.soft->radius * p.soft->radius;
  return p.soft_rho2 * (d2 + r2) <= r2 * d2;
}

// What a deposit tells of its photon's path besides its flux.
struct PhotonTag {
  bool caustic;    // it came by specular scatterings only (PhotonPath::caustic)
  int32_t origin;  // PhotonPath::origin
};

// Emits a photon from light `index`, picked with probability `pick_pdf` (rng drew the pick); with a
// guide, a guided light's direction comes from its histogram (photon_guide.h).
inline PhotonPath emit_photon_path_from(const Scene& scene, const LightSampler& lights, const BounceLimits& limits,
                                        Rng rng, uint32_t index, double pick_pdf, const PhotonGuide* guide) {
  const Light& light = scene.lights()[index];
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform(), u5 = rng.uniform();
  PhotonEmission e;
  int32_t origin = -1;
  const int slot = guide ? guide->slot(index) : -1;
  if (slot >= 0 && guide->learned(slot)) {
    uint32_t bin;
    double ratio;
    const Vec3 d = guide->sample(slot, u3, u4, bin, ratio);
    e = emit_photon_towards(light, d, u1, u2);
    e.flux /= ratio;
    origin = slot * PhotonGuide::kBins + static_cast<int32_t>(bin);
  } else {
    e = emit_photon(light, u1, u2, u3, u4, u5);
    // Not guided yet: its bin all the same, for the credits the guide first learns from.
    if (slot >= 0) origin = slot * PhotonGuide::kBins + static_cast<int32_t>(guide->bin_of(slot, e.ray.direction));
  }
  // On its way from the light a photon carries direct light, which Cycles
  // traces with shadow rays: it passes through what casts no shadow.
  e.ray.kind = kShadowRay;
  const Bounces start = limits.active ? limits.start(light) : Bounces{};
  PhotonPath path{rng, e.flux / (pick_pdf * lights.flux_unit()), e.ray, 0, start};  // its share of the total
  path.origin = origin;
  if (light.soft_falloff && e.rho2 >= 0.0) path.soft = &light, path.soft_rho2 = e.rho2;
  return path;
}

// Emits a photon from a light picked in proportion to its flux (emit_photon_path_from).
inline PhotonPath emit_photon_path(const Scene& scene, const LightSampler& lights, const BounceLimits& limits,
                                   Rng rng, const PhotonGuide* guide = nullptr) {
  double pick_pdf;
  const uint32_t index = lights.pick_emitter(rng.uniform(), pick_pdf);
  return emit_photon_path_from(scene, lights, limits, rng, index, pick_pdf, guide);
}

// Takes the path one bounce on, given what its ray hit (nullptr: nothing):
// deposits (counted in `deposits`), then scatters. False when the path ends.
// `deposit_direct`: a first hit deposits too (its light is not sampled at hit points:
// direct_light="photons", or a photon of an emitting medium, photon_tracer_media.h).
// `deposit(position, travel_direction, normal, flux, bounces, tag)`, where `normal`
// is the surface's shading normal turned to the side the photon arrived on (as
// hit points turn theirs to the viewer), `bounces` the path's counts with
// the hit point's own scattering (meaningful only when `limits.active`), and `tag` what else
// the deposit tells of the path (PhotonTag).
template <class Deposit>
bool bounce_photon(const Scene& scene, const Settings& settings, const BounceLimits& limits, PhotonPath& p,
                   const Hit* hit, bool deposit_direct, Deposit&& deposit, uint64_t& deposits) {
  if (hit == nullptr || !soft_falloff_reaches(p, hit->position)) return false;
  const Material& m = scene.material(hit->material);
  if (is_black(m)) return false;
  const Vec3 wo = -p.ray.direction;
  LightPath path = kCameraPath;  // see LightPath: photons know only their own side of the path
  path.kind = p.ray.kind;
  path.depth = capped(p.bounce + 1);
  path.length = static_cast<float>(hit->t);
  const SurfacePoint sp = scene.surface_point(*hit, wo, 0.0, path);
  if (!is_specular(m) && (p.bounce > 0 || deposit_direct)) {
    const uint8_t here = scattering_ray_kind(m);
    const Bounces bounces = limits.active && p.bounce > 0 ? plus(p.used, here) : p.used;
    deposit(hit->position, p.ray.direction, glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns, p.flux, bounces,
            PhotonTag{p.caustic(), p.origin});
    ++deposits;
  }
  BsdfSample s;
  const double v1 = p.rng.uniform(), v2 = p.rng.uniform(), v3 = p.rng.uniform();
  const double v4 = m.kind == MaterialKind::Mixture ? p.rng.uniform() : 0.0;
  if (!bsdf_sample(m, sp, wo, v1, v2, v3, v4, true, s)) return false;
  // Russian roulette on the scattering weight keeps the flux per photon steady.
  const double survive = std::fmin(1.0, max_component(s.weight));
  if (!(survive > 0.0) || p.rng.uniform() >= survive) return false;
  p.flux *= s.weight / survive;
  if (s.ray_kind != 0) {  // transparency is no scattering
    const bool specular = s.specular || is_specular(m);
    p.specular_only = specular && (p.specular_only || !p.scattered);
    p.scattered = true;
  }
  p.ray = Ray{offset_point(hit->position, hit->geometric_normal, s.wi, scene.offset_floor()), s.wi,
              s.ray_kind ? s.ray_kind : p.ray.kind};  // 0: through a transparent surface
  if (limits.active) {
    if (p.bounce > 0) p.used = plus(p.used, p.ray.kind);
    // Every later deposit adds the hit point's own scattering to the total.
    if (!within(p.used, limits.max) || p.used.total >= limits.max.total) return false;
  }
  return ++p.bounce < settings.path_bounces();
}

constexpr int kPhotonWave = 64;  // paths live at a time in a wave

// Traces photons [first, last), photon i with the random numbers of
// `rng_of(i)`, guided by `guide` if given; returns the number of deposits.
template <class RngOf, class Deposit>
uint64_t trace_photons(const Scene& scene, const LightSampler& lights, const Settings& settings,
                       const BounceLimits& limits, uint64_t first, uint64_t last, RngOf&& rng_of, Deposit&& deposit,
                       const PhotonGuide* guide = nullptr) {
  uint64_t deposits = 0;
  const bool deposit_direct = settings.direct_light == DirectLight::Photons;
  if (!scene.interleaves_walks()) {  // a BVH in cache gains nothing from waves: one photon after the other
    for (uint64_t i = first; i < last; ++i) {
      PhotonPath p = emit_photon_path(scene, lights, limits, rng_of(i), guide);
      Hit hit;
      while (scene.intersect(p.ray, hit) &&
             bounce_photon(scene, settings, limits, p, &hit, deposit_direct, deposit, deposits)) {
      }
    }
    return deposits;
  }
  PhotonPath paths[kPhotonWave];
  Ray rays[kPhotonWave];
  Hit hits[kPhotonWave];
  int live = 0;
  uint64_t next = first;
  for (;;) {
    for (; live < kPhotonWave && next < last; ++next)
      paths[live++] = emit_photon_path(scene, lights, limits, rng_of(next), guide);
    if (live == 0) return deposits;
    for (int k = 0; k < live; ++k) rays[k] = paths[k].ray;
    scene.intersect_many(rays, live, hits);
    int kept = 0;
    for (int k = 0; k < live; ++k) {
      const Hit* hit = hits[k].found() ? &hits[k] : nullptr;
      if (bounce_photon(scene, settings, limits, paths[k], hit, deposit_direct, deposit, deposits))
        paths[kept++] = paths[k];
    }
    live = kept;
  }
}

}  // namespace ppm
