// Emitting media as lights (scene/medium_lights.cpp): a closed mesh whose material carries an
// emitting medium becomes a light of kind Medium of flux 4 pi L_e V; the inside test (ray parity
// against the region's own triangles) agrees with the shape's own test on a non-convex L-shaped
// prism with other geometry through it; its points are uniform; what cannot emit is noted.
#include "math/rng.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace ppm {
namespace {

// The L of area 3: {0 <= x <= 2, 0 <= y <= 1} and {0 <= x <= 1, 0 <= y <= 2}, extruded to z in [0, 1].
bool in_l(const Vec3& p) {
  if (p.z < 0.0 || p.z > 1.0 || p.x < 0.0 || p.y < 0.0) return false;
  return (p.x <= 2.0 && p.y <= 1.0) || (p.x <= 1.0 && p.y <= 2.0);
}

MeshInput l_prism_mesh(uint32_t material, uint32_t object) {
  const Vec2 outline[6] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  MeshInput m;
  m.name = "L";
  for (double z : {0.0, 1.0})
    for (const Vec2& c : outline) m.positions.push_back(Vec3(c.x, c.y, z));  // bottom 0-5, top 6-11
  auto tri = [&](uint32_t a, uint32_t b, uint32_t c) { m.triangles.insert(m.triangles.end(), {a, b, c}); };
  for (uint32_t k : {4u, 5u, 0u, 1u}) {
    tri(9, 6 + k, 6 + (k + 1) % 6);
    tri(3, (k + 1) % 6, k);
  }
  for (uint32_t i = 0; i < 6; ++i) {
    const uint32_t j = (i + 1) % 6;
    tri(i, j, 6 + j);
    tri(i, 6 + j, 6 + i);
  }
  m.materials = {material};
  m.object_id = object;
  return m;
}

// A box from lo to hi, facing outward.
MeshInput box_mesh(const Vec3& lo, const Vec3& hi, uint32_t material, uint32_t object) {
  MeshInput m;
  m.name = "box";
  for (int i = 0; i < 8; ++i)
    m.positions.push_back(Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z));
  const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) m.triangles.insert(m.triangles.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
  m.materials = {material};
  m.object_id = object;
  return m;
}

// An L of glowing medium (emission 2, 0.5, 0.25 per metre) and a diffuse box through its arm.
Scene glowing_l() {
  Scene scene;
  Medium glow;
  glow.name = "glow";
  glow.c.sigma_a = Color(0.5);
  glow.c.emission = Color(2.0, 0.5, 0.25);
  const uint32_t medium = scene.add_medium(glow);
  Material boundary;
  boundary.name = "glow";
  const uint32_t material = scene.add_material(boundary);
  scene.set_material_medium(material, static_cast<int>(medium), false);
  Material wood;
  wood.name = "wood";
  const uint32_t other = scene.add_material(wood);
  scene.add_mesh(l_prism_mesh(material, 1));
  scene.add_mesh(box_mesh(Vec3(0.5, -0.5, 0.2), Vec3(1.5, 1.5, 0.6), other, 2));
  scene.build();
  return scene;
}

TEST(MediumLights, ClosedEmittingMeshIsALightOfItsVolumesPower) {
  const Scene scene = glowing_l();
  ASSERT_EQ(scene.lights().size(), 1u);
  const Light& l = scene.lights()[0];
  EXPECT_EQ(l.kind, LightKind::Medium);
  EXPECT_NEAR(l.volume, 3.0, 1e-12);
  EXPECT_NEAR(l.flux.x, 4.0 * kPi * 2.0 * 3.0, 1e-9);
  EXPECT_NEAR(l.flux.z, 4.0 * kPi * 0.25 * 3.0, 1e-9);
  EXPECT_EQ(scene.medium_region(l.region).object, 1u);
  EXPECT_TRUE(scene.light_notes().empty());
}

TEST(MediumLights, InsideByParityAgreesWithTheShape) {
  const Scene scene = glowing_l();
  Rng rng(5, 0, 0);
  int inside = 0, disagree = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = Vec3(-0.5) + 3.0 * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
    Vec3 d(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
    if (!(glm::length(d) > 1e-3)) continue;
    const bool expected = in_l(p);
    inside += expected;
    disagree += scene.inside_medium_region(0, p, glm::normalize(d)) != expected;
  }
  EXPECT_GT(inside, n / 20);  // 3 of the 27 m^3: about 2200
  EXPECT_EQ(disagree, 0);
}

TEST(MediumLights, SampledPointsAreInsideAndUniform) {
  const Scene scene = glowing_l();
  Rng rng(9, 1, 0);
  const int n = 30000;
  int arm = 0, low = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 p;
    ASSERT_TRUE(scene.sample_medium_region(0, rng, p));
    ASSERT_TRUE(in_l(p));
    arm += p.y > 1.0;  // the arm of 1 m^3 of the 3
    low += p.z < 0.2;  // the fifth below the diffuse box
  }
  const double sd_arm = std::sqrt(n * (1.0 / 3.0) * (2.0 / 3.0)), sd_low = std::sqrt(n * 0.2 * 0.8);
  EXPECT_NEAR(arm, n / 3.0, 4.0 * sd_arm);
  EXPECT_NEAR(low, n * 0.2, 4.0 * sd_low);
}

TEST(MediumLights, OpenFlatAndWorldMediaEmitNoPhotonsAndSaySo) {
  Scene scene;
  Medium glow;
  glow.name = "glow";
  glow.c.emission = Color(1.0);
  const uint32_t medium = scene.add_medium(glow);
  Material boundary;
  boundary.name = "glow";
  const uint32_t material = scene.add_material(boundary);
  scene.set_material_medium(material, static_cast<int>(medium), false);
  MeshInput open = box_mesh(Vec3(0.0), Vec3(1.0), material, 1);
  open.triangles.resize(open.triangles.size() - 6);  // no +x side
  scene.add_mesh(open);
  MeshInput sheet = box_mesh(Vec3(2.0), Vec3(3.0, 3.0, 2.0), material, 2);  // no height: encloses nothing
  scene.add_mesh(sheet);
  scene.set_world_medium(static_cast<int>(medium));
  scene.build();
  EXPECT_TRUE(scene.lights().empty());
  ASSERT_EQ(scene.light_notes().size(), 3u);
  EXPECT_NE(scene.light_notes()[0].find("world medium"), std::string::npos);
  EXPECT_NE(scene.light_notes()[1].find("4 open edges"), std::string::npos);
  EXPECT_NE(scene.light_notes()[2].find("no volume"), std::string::npos);
}

}  // namespace
}  // namespace ppm
