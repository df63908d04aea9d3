// The microfiber sheen (shading/microfiber_sheen.h): its table agrees with random walks through
// the fibre layer it models, simulated here independently of the script that fitted it (normals
// drawn by rejection from the SGGX distribution rather than by the script's ellipsoid mapping);
// the lobe samples as it evaluates, for eye paths and photons; it creates no energy and, as a
// layer, a white one over white diffuse loses nothing.
#include "lobe_test_helpers.h"
#include "math/rng.h"
#include "math/sampling.h"
#include "shading/closure.h"
#include "shading/microfacet.h"
#include "shading/microfiber_sheen.h"
#include "random_test_helpers.h"

#include <gtest/gtest.h>

namespace ppm {
namespace {

// The fibre layer (tools/sheen_ltc/fit_sheen_ltc.py): unit thickness and density, no absorption,
// SGGX S = diag(1, 1, roughness^4), a specular microflake phase function, at most 16 scatterings.
struct FibreLayer {
  double s_zz;
  double projected_area(const Vec3& w) const { return std::sqrt(w.x * w.x + w.y * w.y + s_zz * w.z * w.z); }
  // SGGX's D up to a constant: 1 / (w^T S^-1 w)^2; largest for horizontal w.
  double d(const Vec3& w) const {
    const double q = w.x * w.x + w.y * w.y + w.z * w.z / s_zz;
    return 1.0 / (q * q);
  }
  // A flake normal visible from v: density ~ max(0, v.m) D(m), by rejection.
  Vec3 visible_normal(const Vec3& v, Rng& rng) const {
    for (;;) {
      const Vec3 m = sample_uniform_sphere(rng.uniform(), rng.uniform());
      if (rng.uniform() < std::fmax(glm::dot(v, m), 0.0) * d(m)) return m;
    }
  }
  // Where a walk entering towards -view ends: up means reflected.
  Vec3 walk(const Vec3& view, Rng& rng) const {
    Vec3 dir = -view;
    double depth = 0.0;
    for (int bounce = 0; bounce < 16; ++bounce) {
      depth += -std::log(1.0 - rng.uniform()) / projected_area(dir) * -dir.z;
      if (depth < 0.0 || depth > 1.0) break;
      const Vec3 m = visible_normal(-dir, rng);
      dir = reflect(-dir, m);
    }
    return dir;
  }
};

TEST(MicrofiberSheen, TheTableAgreesWithRandomWalksThroughTheFibreLayer) {
  // Grid nodes of the table, (mu index, roughness index) out of 31, and coarse bins of the reflected
  // light: three bands of theta, towards the viewer's side (x > 0) or away.
  for (auto [mu_index, r_index] : {std::pair{15, 31}, std::pair{3, 16}, std::pair{31, 20}, std::pair{8, 24}}) {
    const double mu = mu_index / 31.0, roughness = r_index / 31.0;
    const FibreLayer layer{std::pow(roughness, 4.0)};
    const Vec3 view = direction(mu);
    Rng rng(21, 22, 23);
    const int walks = 200000;
    double walked[6] = {}, fitted[6] = {};
    int up = 0;
    auto bin = [](const Vec3& w) {
      return std::min(static_cast<int>(std::acos(w.z) / (kPi / 6.0)), 2) * 2 + (w.x > 0.0);
    };
    for (int i = 0; i < walks; ++i) {
      const Vec3 out = layer.walk(view, rng);
      if (out.z > 0.0) {
        ++up;
        walked[bin(out)] += 1.0 / walks;
      }
    }
    const double albedo = static_cast<double>(up) / walks;
    EXPECT_NEAR(microfiber_sheen_albedo(roughness, mu), albedo, 0.004 + 0.01 * albedo) << mu << " " << roughness;
    for (int i = 0; i < walks; ++i) {
      BsdfSample s;
      if (microfiber_sheen_sample(Color(1.0), roughness, kFlat, view, rng.uniform(), rng.uniform(), false, s))
        fitted[bin(s.wi)] += s.weight.x / walks;
    }
    // The fit approximates the layer's shape: within 5% of the albedo in each bin (3.6% measured).
    for (int b = 0; b < 6; ++b)
      EXPECT_NEAR(fitted[b], walked[b], 0.05 * albedo + 0.003) << mu << " " << roughness << " bin " << b;
  }
}

TEST(MicrofiberSheen, AlbedoGrowsTowardsGrazingViewsAndWithRoughness) {
  EXPECT_LT(microfiber_sheen_albedo(0.5, 1.0), 0.05);
  EXPECT_GT(microfiber_sheen_albedo(0.5, 0.1), 0.4);
  EXPECT_LT(microfiber_sheen_albedo(0.2, 0.5), microfiber_sheen_albedo(0.8, 0.5));
  for (double r : {0.0, 0.3, 1.0})
    for (double mu : {0.0, 0.4, 1.0}) {
      EXPECT_GE(microfiber_sheen_albedo(r, mu), 0.0);
      EXPECT_LT(microfiber_sheen_albedo(r, mu), 1.0);
    }
}

Lobe sheen_lobe(double roughness, bool layer = false) {
  Lobe l;
  l.kind = LobeKind::MicrofiberSheen;
  l.color = Color(1.0);
  l.roughness = roughness;
  l.layer = layer;
  prepare_lobe(l);
  return l;
}

// Mean sampled weight against the integral of f cos over the hemisphere (adjoint: f(wi, wo) cos wi).
void expect_sampling_matches_eval(const std::vector<Lobe>& lobes, const Vec3& wo, bool adjoint) {
  Rng rng(5, 6, 7);
  const int n = test_samples(200000);
  double sampled = 0.0, integrated = 0.0;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    if (closure_sample(lobes, kFlat, wo, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(), adjoint, s))
      sampled += s.weight.x;
    for (int k = 0; k < 8; ++k) {
      const Vec3 wi = sample_uniform_sphere((k + rng.uniform()) / 8.0, rng.uniform());
      const Color f = adjoint ? closure_eval(lobes, kFlat, wi, wo) : closure_eval(lobes, kFlat, wo, wi);
      integrated += f.x * std::fabs(wi.z) * 4.0 * kPi / 8.0;
    }
  }
  EXPECT_NEAR(sampled / n, integrated / n, 0.01) << (adjoint ? "photons" : "eye") << " cos " << wo.z;
}

TEST(MicrofiberSheen, SamplesAsItEvaluatesForEyePathsAndPhotons) {
  for (double roughness : {0.2, 0.5, 1.0})
    for (double cos_o : {0.95, 0.5, 0.15}) {
      const std::vector<Lobe> lobes = {sheen_lobe(roughness)};
      expect_sampling_matches_eval(lobes, direction(cos_o, 0.3), false);
      expect_sampling_matches_eval(lobes, direction(cos_o, 0.3), true);
    }
}

TEST(MicrofiberSheen, AWhiteSheenLayerOverWhiteDiffuseLosesNothing) {
  Lobe diffuse;
  diffuse.color = Color(1.0);
  for (double roughness : {0.3, 1.0}) {
    const std::vector<Lobe> lobes = {sheen_lobe(roughness, true), diffuse};
    for (double cos_o : {0.9, 0.5, 0.15}) {
      Rng rng(11, 12, 13);
      const int n = test_samples(200000);
      double sum = 0.0;
      for (int i = 0; i < n; ++i) {
        BsdfSample s;
        if (closure_sample(lobes, kFlat, direction(cos_o), rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform(),
                           false, s))
          sum += s.weight.x;
      }
      EXPECT_NEAR(sum / n, 1.0, 0.01) << roughness << " " << cos_o;
    }
  }
}

}  // namespace
}  // namespace ppm
