// Photons traced in waves (trace_photons on a scene large enough for
// interleaved BVH walks) must deposit exactly what each photon deposits when
// traced alone, bounce by bounce; only the order of deposits may differ.
#include "ppm/photon_tracer.h"
#include "math/rng.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace ppm {
namespace {

using Deposit = std::array<double, 13>;  // position, direction, normal, flux, caustic

// A closed room of 4 large quads plus a soup of 40,000 small triangles (a
// BVH beyond kInterleaveBytes), a glass ball and a point light.
Scene large_room() {
  Rng rng(2, 7, 1);
  Scene scene;
  Material white;
  white.name = "white";
  scene.add_material(white);
  Material glass;
  glass.name = "glass";
  glass.kind = MaterialKind::Glass;
  glass.base_color = Color(1.0);
  scene.add_material(glass);
  MeshInput mesh;
  mesh.name = "room";
  const double h = 5.0;
  for (const Vec3& p : {Vec3(-h, -h, -h), Vec3(h, -h, -h), Vec3(h, h, -h), Vec3(-h, h, -h), Vec3(-h, -h, h),
                        Vec3(h, -h, h), Vec3(h, h, h), Vec3(-h, h, h)})
    mesh.positions.push_back(p);
  mesh.triangles = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
  for (uint32_t i = 0; i < 40000; ++i) {
    const Vec3 c = 8.0 * unit_cube(rng);
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    for (int k = 0; k < 3; ++k) mesh.positions.push_back(c + 0.1 * unit_cube(rng));
    for (uint32_t k = 0; k < 3; ++k) mesh.triangles.push_back(base + k);
  }
  mesh.materials = {0};
  scene.add_mesh(mesh);
  scene.add_sphere("ball", Vec3(1.0, 0.5, -1.0), 1.0, 1, 2);
  Light light;
  light.name = "lamp";
  light.kind = LightKind::Point;
  light.position = Vec3(0.0, 0.0, 3.0);
  light.power = Color(100.0);
  scene.add_light(light);
  scene.build();
  return scene;
}

TEST(PhotonWaves, SameDepositsAsOnePhotonAtATime) {
  const Scene scene = large_room();
  ASSERT_TRUE(scene.interleaves_walks());
  const LightSampler lights(scene.lights());
  for (const DirectLight direct : {DirectLight::Sampled, DirectLight::Photons}) {
    Settings settings;
    settings.direct_light = direct;
    settings.max_bounces = 6;
    auto rng_of = [](uint64_t i) { return Rng(5, 9, i); };
    const uint64_t photons = 3000;  // many waves of 64, and a last partial one

    std::vector<Deposit> waves;
    auto record = [](std::vector<Deposit>& out) {
      return [&out](const Vec3& p, const Vec3& d, const Vec3& n, const Color& f, const Bounces&, PhotonTag tag) {
        out.push_back({p.x, p.y, p.z, d.x, d.y, d.z, n.x, n.y, n.z, f.x, f.y, f.z, tag.caustic ? 1.0 : 0.0});
      };
    };
    const BounceLimits limits = BounceLimits::of(settings, scene);
    const uint64_t counted = trace_photons(scene, lights, settings, limits, 0, photons, rng_of, record(waves));

    std::vector<Deposit> alone;
    uint64_t deposits = 0;
    int longest = 0;
    for (uint64_t i = 0; i < photons; ++i) {
      PhotonPath p = emit_photon_path(scene, lights, limits, rng_of(i));
      Hit hit;
      const bool deposit_direct = settings.direct_light == DirectLight::Photons;
      while (scene.intersect(p.ray, hit) &&
             bounce_photon(scene, settings, limits, p, &hit, deposit_direct, record(alone), deposits)) {
      }
      longest = std::max(longest, p.bounce);
    }
    EXPECT_EQ(counted, waves.size());
    EXPECT_EQ(deposits, alone.size());
    ASSERT_GT(alone.size(), photons / 2);
    EXPECT_GE(longest, 3) << "some paths should bounce several times";
    std::sort(waves.begin(), waves.end());
    std::sort(alone.begin(), alone.end());
    ASSERT_EQ(waves, alone);
  }
}

}  // namespace
}  // namespace ppm
