// Light from an image around the scene (Blender's Environment Texture in the
// world): the radiance arriving from each direction, and the density the
// renderer samples directions by, so that a small bright sun in a large sky
// is found by direct light and photons alike.
//
// Directions map to the image as in Cycles (`direction_to_equirectangular`,
// `direction_to_mirrorball`), after `world_to_texture` (the Mapping node's
// rotation). Sampling uses a latitude-longitude grid in world space whose
// cells weigh their mean luminance times their solid angle, plus a floor of
// 1e-3 of the mean so that no direction with light has density zero.
#pragma once

#include "math/distribution_2d.h"
#include "math/types.h"
#include "shading/texture.h"

#include <glm/mat3x3.hpp>

namespace ppm {

enum class EnvironmentProjection : uint8_t { Equirectangular, MirrorBall };

using Mat3 = glm::dmat3;

class Environment {
 public:
  // `texture` must outlive the environment. `world_to_texture` must be a rotation.
  Environment(const Texture* texture, const Mat3& world_to_texture, const Color& strength,
              EnvironmentProjection projection);

  // Radiance arriving from unit direction `dir` (pointing away from the scene).
  Color radiance(const Vec3& dir) const;
  // A direction by the sampling density; pdf over solid angle. False if the environment is black.
  bool sample(double u1, double u2, Vec3& dir, double& pdf) const;
  double pdf(const Vec3& dir) const;
  // The integral of the radiance over the sphere of directions (W/m^2 per unit cross-section).
  const Color& integral() const { return integral_; }

 private:
  const Texture* texture_;
  Mat3 world_to_texture_;
  Color strength_;
  EnvironmentProjection projection_;
  int grid_width_ = 0, grid_height_ = 0;
  Distribution2D distribution_;
  Color integral_{0.0};
};

}  // namespace ppm
