// Photons leave lights where their light goes: a spot's photons inside its cone, a soft box's within
// its spread, each carrying about the mean flux. Drawn from the whole sphere or hemisphere and
// weighted by the mask instead, a narrow spot wasted nearly every photon and gave the rest a
// thousand times the flux (single photons showed as specks in fog), unbiased but useless.
#include "math/rng.h"
#include "math/sampling.h"
#include "scene/light.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ppm {
namespace {

constexpr int kPhotons = 200000;

Light narrow_spot(double radius) {
  Light l;
  l.kind = LightKind::Spot;
  l.power = Color(1000.0);
  l.position = Vec3(1.0, 2.0, 3.0);
  l.direction = Vec3(0.0, 0.0, -1.0);
  l.radius = radius;
  l.cos_half_spot = std::cos(3.5 * kPi / 180.0);
  l.spot_smooth = (1.0 - l.cos_half_spot) * 0.15;
  prepare_light(l, Aabb{Vec3(-10.0), Vec3(10.0)});
  return l;
}

PhotonEmission emit(const Light& l, Rng& rng) {
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform(), u4 = rng.uniform(), u5 = rng.uniform();
  return emit_photon(l, u1, u2, u3, u4, u5);
}

TEST(PhotonEmission, SphereSpotPhotonsLeaveItsFrontInsideTheCone) {
  const Light l = narrow_spot(0.1);
  Rng rng(11, 12, 13);
  double sum = 0.0, most = 0.0, moment = 0.0, spread2 = 0.0;
  int carrying = 0;
  for (int i = 0; i < kPhotons; ++i) {
    const PhotonEmission e = emit(l, rng);
    const Vec3 from_centre = e.ray.origin - l.position;
    ASSERT_NEAR(glm::length(from_centre), l.radius, 1e-12);
    ASSERT_GE(glm::dot(from_centre, e.ray.direction), -1e-12);  // leaves the sphere outwards
    const double c = glm::dot(e.ray.direction, l.direction);
    sum += e.flux.x;
    most = std::max(most, e.flux.x);
    moment += e.flux.x * c * c * c * c;
    carrying += e.flux.x > 0.0;
    // Seen along its direction, the origin lies uniformly on the sphere's outline: E[rho^2] = R^2 / 2.
    const Vec3 across = from_centre - glm::dot(from_centre, e.ray.direction) * e.ray.direction;
    spread2 += glm::dot(across, across);
  }
  EXPECT_NEAR(sum / kPhotons / l.flux.x, 1.0, 0.01);
  EXPECT_GE(carrying, kPhotons - kPhotons / 1000);  // none wasted (but on the cone's very edge)
  EXPECT_LE(most, 2.0 * l.flux.x);
  EXPECT_NEAR(spread2 / kPhotons, 0.5 * l.radius * l.radius, 0.01 * l.radius * l.radius);
  // The same directions, flux for flux, as the spot without a radius (the mask is the direction's).
  const Light point = narrow_spot(0.0);
  double point_moment = 0.0;
  for (int i = 0; i < kPhotons; ++i) {
    const PhotonEmission e = emit(point, rng);
    const double c = glm::dot(e.ray.direction, point.direction);
    point_moment += e.flux.x * c * c * c * c;
  }
  EXPECT_NEAR(moment / point_moment, 1.0, 1e-3);
}

TEST(PhotonEmission, SpreadAreaLightPhotonsLeaveWithinTheSpread) {
  Light l;
  l.kind = LightKind::Disk;
  l.power = Color(50.0);
  l.position = Vec3(0.0, 0.0, 2.0);
  l.direction = Vec3(0.0, 0.0, -1.0);
  l.axis_u = Vec3(0.25, 0.0, 0.0);
  l.axis_v = Vec3(0.0, 0.25, 0.0);
  l.spread = 30.0 * kPi / 180.0;
  prepare_light(l, Aabb{Vec3(-1.0), Vec3(1.0)});
  const double h = 0.5 * l.spread;
  // What the flux times cos^2 of the angle to the axis averages to: the attenuation over the
  // cosine-weighted hemisphere, integrated over the angle a (midpoint rule).
  constexpr int kSteps = 200000;
  double expected = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double a = (i + 0.5) * (kPi / 2.0) / kSteps, c = std::cos(a);
    expected += spread_attenuation(l, c) * c * c * (c / kPi) * 2.0 * kPi * std::sin(a) * (kPi / 2.0) / kSteps;
  }
  Rng rng(21, 22, 23);
  double sum = 0.0, moment = 0.0, most = 0.0;
  for (int i = 0; i < kPhotons; ++i) {
    const PhotonEmission e = emit(l, rng);
    const double c = glm::dot(e.ray.direction, l.direction);
    ASSERT_GE(c, std::cos(h) - 1e-12);
    sum += e.flux.x;
    moment += e.flux.x * c * c;
    most = std::max(most, e.flux.x);
  }
  EXPECT_NEAR(sum / kPhotons / l.flux.x, 1.0, 0.01);
  EXPECT_NEAR(moment / kPhotons / l.flux.x, expected, 0.01 * expected);
  EXPECT_LE(most, 4.0 * l.flux.x);
}

}  // namespace
}  // namespace ppm
