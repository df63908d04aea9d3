// Photon paths in scenes with participating media (scene/medium.h): as photon_tracer.h, and on
// every ray the photon samples a free path in the medium it is in (shading/free_path.h, Cycles'
// chromatic distance sampling). A collision before the surface is a scattering event: the photon
// is stored there as a VOLUME photon (its own list and grid, photon_pass.h), with its flux times the
// free path's weight sigma_s T / pdf, so that the stored flux per volume estimates sigma_s times the
// fluence; then Russian roulette on that weight and the phase function sampled (its value equals its
// pdf, so the flux is unchanged). Otherwise the photon reaches the surface with the weight of
// getting there (T / P(no collision); T itself in a medium that only absorbs). Boundaries without a
// surface are crossed, and refractions through a surface with a medium change the medium stack.
//
// Emitting media are lights too (scene/light.h, LightKind::Medium): a photon picked from one
// starts at a uniform point inside its region (Scene::sample_medium_region) in a uniform direction,
// inside that medium and those around it (a glowing cloud in a fog room: both on its stack). No light sampling reaches such a light, so its photons
// deposit from their first hit, surface or volume, as every photon does with direct_light="photons".
// The eye sees the emission itself along its rays (medium_emission_along), never by photons: a
// photon reaches the eye only through a hit point's gather, after a scattering there.
//
// Scenes without media never come here (PhotonPass picks photon_tracer.h's trace_photons). Paths
// are traced one after the other (no waves yet).
#pragma once

#include "math/sampling.h"
#include "ppm/photon_beams.h"
#include "ppm/photon_tracer.h"
#include "shading/free_path.h"

namespace ppm {

// Whether p's light reaches a medium only along specular bounces, or none: the light that photon
// beams carry (photon_beams.h) with Settings::volume_beams, in homogeneous media.
inline bool specular_chain(const PhotonPath& p) { return !p.scattered || p.specular_only; }

// The scattering event at distance f.distance along p's ray in medium `med`: a volume photon
// deposited (after the first bounce unless `deposit_direct`, see bounce_photon; `beamed` where a
// photon beam carried the way here), then the phase function sampled. False when the path ends.
template <class DepositVolume>
bool scatter_photon_in_medium(const Settings& settings, const BounceLimits& limits, PhotonPath& p, const Medium& med,
                              const FreePathSample& f, bool deposit_direct, bool beamed,
                              DepositVolume&& deposit_volume, uint64_t& deposits) {
  const Vec3 x = p.ray.origin + f.distance * p.ray.direction;
  if (!soft_falloff_reaches(p, x)) return false;
  p.flux *= f.weight;
  if (p.bounce > 0 || deposit_direct) {
    // With bounce limits: the path's counts with the hit point's own scattering here.
    deposit_volume(x, p.ray.direction, p.flux, limits.active && p.bounce > 0 ? plus_volume(p.used) : p.used, beamed);
    ++deposits;
  }
  const double survive = std::fmin(1.0, max_component(f.weight));
  if (!(survive > 0.0) || p.rng.uniform() >= survive) return false;
  p.flux /= survive;
  const double u1 = p.rng.uniform(), u2 = p.rng.uniform();
  const PhaseSample s = med.c.phase.sample(p.ray.direction, u1, u2);
  if (!(s.pdf > 0.0)) return false;
  p.specular_only = false;
  p.scattered = true;
  // The ray goes on as a diffuse one for ray visibility and the Light Path node (Cycles has a
  // volume-scatter kind of its own); the bounce counts below count it as a volume scattering.
  p.ray = Ray{x, s.direction, kDiffuseRay};
  if (limits.active) {
    if (p.bounce > 0) p.used = plus_volume(p.used);  // counted as Cycles counts it (bounce_limits.h)
    if (!within(p.used, limits.max) || p.used.total >= limits.max.total) return false;
  }
  return ++p.bounce < settings.path_bounces();
}

// A photon's start in a scene with media: its path, the media it is in, whether it left an emitting
// medium (its first hit then deposits), and false `emitted` where it carries nothing: no point of its
// region was found, or it came from infinitely far through a world medium that leaves none of it.
struct MediaPhoton {
  PhotonPath path;
  MediumStack media;  // the light's (Light::media)
  bool from_medium = false;
  bool emitted = true;
};

// Picks a light as emit_photon_path does (the same random numbers for the same lights); a medium's
// photon starts inside its region, uniform in position and direction, carrying its share of the
// total as every photon (flux / (pick pdf * flux_unit)).
inline MediaPhoton emit_media_photon(const Scene& scene, const LightSampler& lights, const BounceLimits& limits,
                                     Rng rng, const PhotonGuide* guide) {
  double pick_pdf;
  const uint32_t index = lights.pick_emitter(rng.uniform(), pick_pdf);
  const Light& light = scene.lights()[index];
  MediaPhoton out;
  if (light.kind != LightKind::Medium) {
    out.path = emit_photon_path_from(scene, lights, limits, rng, index, pick_pdf, guide);
    out.media = light.straddles_media ? scene.media_along(light.media, light.position, out.path.ray.origin, kShadowRay)
                                      : light.media;
    // Light from infinitely far crossed an infinite stretch of the world medium first: nothing of it
    // is left where that medium has extinction (Cycles: a world volume leaves suns and the world's
    // light no effect), as the eye's and hit points' rays to it find.
    const bool from_infinity = light.kind == LightKind::Sun || light.kind == LightKind::Background;
    if (from_infinity && scene.world_medium() >= 0) {
      out.path.flux *= transmittance(scene.media()[scene.world_medium()].sigma_t, kInf);
      out.emitted = max_component(out.path.flux) > 0.0;
    }
    return out;
  }
  Vec3 x;
  out.emitted = scene.sample_medium_region(light.region, rng, x);
  const double u1 = rng.uniform(), u2 = rng.uniform();
  // A shadow ray, as every photon leaving its light (emit_photon_path_from).
  const Ray ray{x, sample_uniform_sphere(u1, u2), kShadowRay};
  const Bounces start = limits.active ? limits.start(light) : Bounces{};
  Color flux = light.flux / (pick_pdf * lights.flux_unit());
  const int id = scene.medium_region(light.region).medium;
  const Medium& med = scene.medium(static_cast<uint32_t>(id));
  if (med.varies()) {  // the light's power is its bound's: each photon carries the emission here against it
    const Color e = scene.local_medium(med, x, ray.direction, rng.next_u32() | 1u).emission;
    for (int c = 0; c < 3; ++c) flux[c] *= med.emission_bound[c] > 0.0 ? e[c] / med.emission_bound[c] : 0.0;
    out.emitted = out.emitted && max_component(flux) > 0.0;
  }
  out.path = PhotonPath{rng, flux, ray, 0, start};
  out.media = light.media;  // its own medium on top of those around it (Scene::place_lights_in_media)
  out.from_medium = true;
  return out;
}

// A photon beam's length in float: an endless one (a clear channel in a world medium) ends where
// float does.
inline float beam_length(double distance) { return static_cast<float>(std::fmin(distance, 3.0e38)); }

// Traces photons [first, last) as trace_photons does, through media: surface photons to
// `deposit`, volume photons to `deposit_volume(position, travel_direction, flux, bounces, beamed)`
// (`bounces` as `deposit`'s: the path's counts with the hit point's own scattering, with bounce
// limits), and with Settings::volume_beams the stretches through homogeneous scattering media that
// light reaches along specular chains to `deposit_beam(PhotonBeam)` (photon_beams.h) as well; the
// volume photons at their ends are `beamed`, for the hit points where beams do not gather.
template <class RngOf, class Deposit, class DepositVolume, class DepositBeam>
uint64_t trace_photons_in_media(const Scene& scene, const LightSampler& lights, const Settings& settings,
                                const BounceLimits& limits, uint64_t first, uint64_t last, RngOf&& rng_of,
                                Deposit&& deposit, DepositVolume&& deposit_volume, DepositBeam&& deposit_beam,
                                const PhotonGuide* guide = nullptr) {
  uint64_t deposits = 0;
  const bool photons_direct = settings.direct_light == DirectLight::Photons;
  const bool beams = settings.volume_beams;
  for (uint64_t i = first; i < last; ++i) {
    MediaPhoton start = emit_media_photon(scene, lights, limits, rng_of(i), guide);
    if (!start.emitted) continue;
    PhotonPath& p = start.path;
    MediumStack& media = start.media;
    const bool deposit_direct = photons_direct || start.from_medium;
    int crossings = 0;
    for (;;) {
      Hit hit;
      const bool found = scene.intersect(p.ray, hit);
      if (const Medium* med = scene.medium_of(media)) {
        const double segment = found ? hit.t : kInf;
        if (med->extinction_varies()) {
          const TrackedSegment f = scene.track(*med, p.ray, segment, p.flux, true, false, p.rng);
          if (f.event == FreePathEvent::Scatter) {
            const FreePathSample at{FreePathEvent::Scatter, f.distance, f.weight};
            if (!scatter_photon_in_medium(settings, limits, p, *med, at, deposit_direct, false, deposit_volume,
                                          deposits))
              break;
            continue;
          }
          p.flux *= f.weight;
        } else if (!med->scatters()) {
          p.flux *= transmittance(med->sigma_t, segment);
        } else {
          const double u1 = p.rng.uniform(), u2 = p.rng.uniform();
          const FreePathSample f = sample_free_path(med->sigma_t, med->c.sigma_s, p.flux, segment, u1, u2);
          const bool beamed = beams && !med->varies() && specular_chain(p) && (p.bounce > 0 || deposit_direct);
          if (beamed)
            deposit_beam(PhotonBeam{p.ray.origin, Vec3f(p.ray.direction), beam_length(f.distance), Vec3f(p.flux),
                                    Vec3f(f.channel_pdf), scene.medium_index(med),
                                    limits.active && p.bounce > 0 ? plus_volume(p.used) : p.used});
          if (f.event == FreePathEvent::Scatter) {
            if (!scatter_photon_in_medium(settings, limits, p, *med, f, deposit_direct, beamed, deposit_volume,
                                          deposits))
              break;
            continue;
          }
          p.flux *= f.weight;
        }
        if (!(max_component(p.flux) > 0.0)) break;
      }
      if (!found) break;
      const Material& m = scene.material(hit.material);
      if (!m.surface) {  // a boundary only: the photon goes on in the next medium
        if (++crossings > kMaxMediumCrossings) break;
        scene.cross(hit, p.ray.direction, media);
        p.ray.origin = offset_point(hit.position, hit.geometric_normal, p.ray.direction, scene.offset_floor());
        continue;
      }
      const Vec3 d_in = p.ray.direction;
      if (!bounce_photon(scene, settings, limits, p, &hit, deposit_direct, deposit, deposits)) break;
      const double side_in = glm::dot(d_in, hit.geometric_normal), side_out = glm::dot(p.ray.direction, hit.geometric_normal);
      if (m.medium >= 0 && side_in * side_out > 0.0) scene.cross(hit, d_in, media);  // through the surface
    }
  }
  return deposits;
}

}  // namespace ppm
