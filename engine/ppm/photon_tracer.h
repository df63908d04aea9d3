// One photon path: emitted from a light chosen by flux, scattered by the BSDFs
// with Russian roulette, deposited at every non-specular surface it reaches
// (after its first bounce when direct light is sampled separately).
#pragma once

#include "math/rng.h"
#include "ppm/settings.h"
#include "scene/light_sampler.h"
#include "scene/scene.h"

namespace ppm {

// `deposit(position, travel_direction, normal, flux)`, where `normal` is the
// surface's shading normal turned to the side the photon arrived on (as hit
// points turn theirs to the viewer); returns the number of deposits.
template <class Deposit>
uint32_t trace_photon(const Scene& scene, const LightSampler& lights, const Settings& settings, Rng& rng,
                      Deposit&& deposit) {
  double pick_pdf;
  const Light& light = scene.lights()[lights.pick_emitter(rng.uniform(), pick_pdf)];
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform(), u5 = rng.uniform();
  const PhotonEmission e = emit_photon(light, u1, u2, u3, u4, u5);
  Color flux = e.flux / pick_pdf;
  Ray ray = e.ray;
  const bool deposit_direct = settings.direct_light == DirectLight::Photons;
  uint32_t deposits = 0;
  for (int bounce = 0; bounce < settings.max_bounces; ++bounce) {
    Hit hit;
    if (!scene.intersect(ray, hit)) break;
    const Material& m = scene.material(hit.material);
    if (is_black(m)) break;
    const Vec3 wo = -ray.direction;
    const SurfacePoint sp = scene.surface_point(hit);
    if (!is_specular(m) && (bounce > 0 || deposit_direct)) {
      deposit(hit.position, ray.direction, glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns, flux);
      ++deposits;
    }
    BsdfSample s;
    const double v1 = rng.uniform(), v2 = rng.uniform(), v3 = rng.uniform();
    if (!bsdf_sample(m, sp, wo, v1, v2, v3, s)) break;
    // Russian roulette on the scattering weight keeps the flux per photon steady.
    const double survive = std::fmin(1.0, max_component(s.weight));
    if (!(survive > 0.0) || rng.uniform() >= survive) break;
    flux *= s.weight / survive;
    ray = Ray{offset_point(hit.position, hit.geometric_normal, s.wi, scene.offset_floor()), s.wi};
  }
  return deposits;
}

}  // namespace ppm
