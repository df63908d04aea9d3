// Blender 3.x's valid reflection (shading/valid_reflection.h): a normal whose mirror direction of
// the view is above the surface is kept; one that reflects into the surface is turned towards the
// geometric normal, in their common plane, just enough to reflect to the threshold height.
#include "math/rng.h"
#include "math/sampling.h"
#include "shading/valid_reflection.h"

#include <gtest/gtest.h>

namespace ppm {
namespace {

Vec3 reflection(const Vec3& v, const Vec3& n) { return 2.0 * glm::dot(v, n) * n - v; }

TEST(ValidReflection, KeepsGoodNormalsAndTurnsBadOnesJustEnough) {
  const Vec3 ng(0.0, 0.0, 1.0);
  const Vec3 v = glm::normalize(Vec3(0.6, 0.0, 0.3));  // a grazing view
  const Vec3 mild = glm::normalize(Vec3(0.1, 0.05, 1.0));
  EXPECT_EQ(valid_reflection(ng, v, mild), mild);
  Rng rng(1, 2, 3);
  int turned = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 view = to_world(sample_cosine_hemisphere(rng.uniform(), rng.uniform()), ng);
    if (view.z < 1e-3) continue;
    const Vec3 n = glm::normalize(Vec3(rng.uniform() * 4.0 - 2.0, rng.uniform() * 4.0 - 2.0, 0.05 + rng.uniform()));
    const Vec3 fixed = valid_reflection(ng, view, n);
    const double t = std::fmin(0.9 * view.z, 0.01);
    EXPECT_NEAR(glm::length(fixed), 1.0, 1e-9);
    EXPECT_GE(glm::dot(reflection(view, fixed), ng), t - 1e-6);
    if (glm::dot(reflection(view, n), ng) >= t) {
      EXPECT_EQ(fixed, n);
      continue;
    }
    ++turned;
    // In the plane of ng and n, at exactly the threshold (not turned all the way to ng).
    EXPECT_NEAR(glm::dot(glm::cross(ng, n), fixed), 0.0, 1e-9);
    if (fixed != ng) EXPECT_NEAR(glm::dot(reflection(view, fixed), ng), t, 1e-6);
  }
  EXPECT_GT(turned, 100);
}

}  // namespace
}  // namespace ppm
