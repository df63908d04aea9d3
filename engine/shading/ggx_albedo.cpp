// GGX albedo tables (see ggx_albedo.h).
#include "shading/ggx_albedo.h"

#include "shading/microfacet.h"

#include <algorithm>
#include <array>

namespace ppm {
namespace {

constexpr int kSteps = 32;
constexpr int kSamples = 64;  // per axis: 4096 stratified visible-normal samples per entry

struct Tables {
  std::array<double, kSteps * kSteps> e{};  // [roughness][cos_theta]
  std::array<double, kSteps> e_avg{};
};

double single_scattering(double roughness, double mu) {
  if (roughness <= 0.0) return 1.0;
  mu = std::max(mu, 1e-4);
  const Vec3 wo(std::sqrt(1.0 - mu * mu), 0.0, mu);
  const double a = std::max(roughness * roughness, 1e-4), a2 = a * a;
  double sum = 0.0;
  for (int i = 0; i < kSamples; ++i)
    for (int j = 0; j < kSamples; ++j) {
      const Vec3 h = ggx_sample_vndf(wo, a, (i + 0.5) / kSamples, (j + 0.5) / kSamples);
      const Vec3 wi = reflect(wo, h);
      if (wi.z > 0.0) sum += ggx_g2(wo, wi, a2) / ggx_g1(wo, a2);
    }
  return sum / (kSamples * kSamples);
}

const Tables& tables() {
  static const Tables t = [] {
    Tables out;
    for (int r = 0; r < kSteps; ++r) {
      double avg = 0.0;
      for (int m = 0; m < kSteps; ++m) {
        const double mu = static_cast<double>(m) / (kSteps - 1);
        const double e = single_scattering(static_cast<double>(r) / (kSteps - 1), mu);
        out.e[r * kSteps + m] = e;
        const double end = (m == 0 || m == kSteps - 1) ? 0.5 : 1.0;  // trapezoid rule
        avg += end * 2.0 * e * mu / (kSteps - 1);  // E_avg = 2 * integral of E(mu) mu dmu
      }
      out.e_avg[r] = std::min(1.0, avg);
    }
    return out;
  }();
  return t;
}

// Linear interpolation weights of x in [0, 1] over kSteps samples.
void cell(double x, int& i, double& t) {
  const double s = std::clamp(x, 0.0, 1.0) * (kSteps - 1);
  i = std::min(static_cast<int>(s), kSteps - 2);
  t = s - i;
}

}  // namespace

double ggx_albedo(double roughness, double cos_theta) {
  int r, m;
  double tr, tm;
  cell(roughness, r, tr);
  cell(cos_theta, m, tm);
  const auto& e = tables().e;
  const double lo = (1.0 - tm) * e[r * kSteps + m] + tm * e[r * kSteps + m + 1];
  const double hi = (1.0 - tm) * e[(r + 1) * kSteps + m] + tm * e[(r + 1) * kSteps + m + 1];
  return (1.0 - tr) * lo + tr * hi;
}

double ggx_average_albedo(double roughness) {
  int r;
  double t;
  cell(roughness, r, t);
  const auto& e = tables().e_avg;
  return (1.0 - t) * e[r] + t * e[r + 1];
}

}  // namespace ppm
