// Scene::intersect_many interleaves several rays' BVH walks; each ray must
// still get exactly the hit record Scene::intersect gives it alone, for every
// kind of primitive (triangles, spheres, Bézier revolves, whose test fills the
// whole record) and for rays that hit nothing.
#include "scene/scene.h"
#include "math/rng.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace ppm {
namespace {

// `triangles` small random triangles, 30 spheres and a Bézier revolve.
Scene mixed_scene(Rng& rng, uint32_t triangles) {
  Scene scene;
  Material white;
  white.name = "white";
  scene.add_material(white);
  Material red = white;
  red.name = "red";
  scene.add_material(red);
  MeshInput mesh;
  mesh.name = "soup";
  const double size = 0.3 * std::sqrt(2000.0 / triangles);  // about the same cover for any count
  for (uint32_t i = 0; i < triangles; ++i) {
    const Vec3 c = 4.0 * unit_cube(rng);
    for (int k = 0; k < 3; ++k) mesh.positions.push_back(c + size * unit_cube(rng));
    for (uint32_t k = 0; k < 3; ++k) mesh.triangles.push_back(3 * i + k);
    mesh.uvs.push_back(Vec2(rng.uniform(), rng.uniform()));
    mesh.uvs.push_back(Vec2(rng.uniform(), rng.uniform()));
    mesh.uvs.push_back(Vec2(rng.uniform(), rng.uniform()));
  }
  mesh.materials = {0};
  mesh.object_id = 1;
  scene.add_mesh(mesh);
  for (int i = 0; i < 30; ++i) scene.add_sphere("ball", 4.0 * unit_cube(rng), 0.2, 1, 2);
  Mat4 to_world(1.0);
  to_world[3] = glm::dvec4(0.5, -0.5, -1.0, 1.0);
  scene.add_bezier_revolve("vase", {Vec2(0.5, 0.0), Vec2(1.2, 0.6), Vec2(0.2, 1.2), Vec2(0.6, 2.0)}, false, to_world,
                           1, 3);
  scene.build();
  return scene;
}

// Checks every ray of a batch against the same ray cast alone.
void expect_same_as_alone(const Scene& scene, Rng& rng) {
  std::vector<Ray> rays;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 o = 10.0 * unit_cube(rng);
    rays.push_back(Ray{o, glm::normalize(3.0 * unit_cube(rng) - o)});
  }
  std::vector<Hit> hits(rays.size());
  scene.intersect_many(rays.data(), rays.size(), hits.data());
  int found = 0, objects[4] = {0, 0, 0, 0};
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit one;
    const bool hit = scene.intersect(rays[i], one);
    const Hit& many = hits[i];
    ASSERT_EQ(many.found(), hit) << "ray " << i;
    if (!hit) continue;
    ++found;
    ++objects[one.object];
    ASSERT_EQ(many.t, one.t) << "ray " << i;
    ASSERT_EQ(many.primitive, one.primitive) << "ray " << i;
    ASSERT_EQ(many.object, one.object) << "ray " << i;
    ASSERT_EQ(many.material, one.material) << "ray " << i;
    ASSERT_EQ(many.position, one.position) << "ray " << i;
    ASSERT_EQ(many.geometric_normal, one.geometric_normal) << "ray " << i;
    ASSERT_EQ(many.shading_normal, one.shading_normal) << "ray " << i;
    ASSERT_EQ(many.uv, one.uv) << "ray " << i;
  }
  EXPECT_GT(found, 2500);
  EXPECT_LT(found, 5000);
  for (int object = 1; object <= 3; ++object) EXPECT_GT(objects[object], 20) << "object " << object;
}

TEST(SceneIntersectMany, SameHitsAsOneRayAtATime) {
  Rng rng(8, 1, 8);
  // Large enough for interleaved walks (kInterleaveBytes), and small enough
  // for one ray at a time: both must agree with intersect().
  const Scene large = mixed_scene(rng, 40000);
  ASSERT_TRUE(large.interleaves_walks());
  expect_same_as_alone(large, rng);
  const Scene small = mixed_scene(rng, 2000);
  ASSERT_FALSE(small.interleaves_walks());
  expect_same_as_alone(small, rng);
}

TEST(SceneIntersectMany, EmptySceneAndEmptyBatch) {
  Scene scene;
  scene.build();
  Ray ray{Vec3(0.0), Vec3(0, 0, 1)};
  Hit hit;
  hit.t = 1.0;  // overwritten with a miss
  scene.intersect_many(&ray, 1, &hit);
  EXPECT_FALSE(hit.found());
  scene.intersect_many(nullptr, 0, nullptr);
}

}  // namespace
}  // namespace ppm
