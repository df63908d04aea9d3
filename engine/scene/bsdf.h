// Scattering at a surface: evaluation and sampling of every material kind,
// dispatched by a switch on the kind (no virtual calls in the hot loops).
// Directions point away from the surface: `wo` towards the viewer or the
// previous path vertex, `wi` towards the light or the next vertex.
#pragma once

#include "geometry/ray.h"
#include "scene/material.h"

namespace ppm {

// What the BSDF needs to know about the point it scatters at.
struct SurfacePoint {
  Vec3 ng;       // geometric normal, outward as the primitive defines it
  Vec3 ns;       // shading normal, same hemisphere as ng
  Color albedo;  // base colour, texture applied
};

struct BsdfSample {
  Vec3 wi;
  Color weight;      // f * |cos| / pdf
  bool specular;     // a delta lobe was sampled
};

// f(wo, wi), without the cosine. Zero for delta lobes.
Color bsdf_eval(const Material& m, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi);

// Samples wi given wo. Returns false when the path should end (absorbed, or a
// sample below the surface).
bool bsdf_sample(const Material& m, const SurfacePoint& sp, const Vec3& wo, double u1, double u2,
                 double u3, BsdfSample& out);

// Both branches of a smooth surface, so the eye pass can follow reflection and
// refraction with their Fresnel weights instead of choosing one at random.
// Returns the number of branches written (0 to 2).
int specular_branches(const Material& m, const SurfacePoint& sp, const Vec3& wo, BsdfSample out[2]);

// The RayKind of a ray scattered from `incoming` into `outgoing` at a surface
// of normal `ng`: transmission if it crossed the surface, else glossy, or
// diffuse for a diffuse material.
inline uint8_t scattered_ray_kind(const Material& m, const Vec3& ng, const Vec3& incoming, const Vec3& outgoing) {
  if ((glm::dot(incoming, ng) < 0.0) == (glm::dot(outgoing, ng) < 0.0)) return kTransmissionRay;
  return m.kind == MaterialKind::Diffuse ? kDiffuseRay : kGlossyRay;
}

// Fresnel reflectance of a dielectric for cos_i on the side with index eta_i.
double fresnel_dielectric(double cos_i, double eta_i, double eta_t);

}  // namespace ppm
