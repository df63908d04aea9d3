// Mixtures of lobes (see closure.h).
#include "shading/closure.h"

#include "shading/ggx_albedo.h"
#include "shading/microfacet.h"
#include "shading/microfiber_sheen.h"

#include <cmath>

namespace ppm {
namespace {

// Cycles' estimate of a microfacet lobe's average Fresnel over the hemisphere (Fss), for the
// energy of multiple scattering: analytic for the F82-tint conductor; Kulla and Conty's fit of the
// real dielectric's, put through the generalized Schlick model for a tinted F0.
Color average_fresnel(const Lobe& l, const SurfacePoint& sp) {
  const Color color = l.color_at(sp);
  if (l.kind == LobeKind::Glossy) return color;
  if (l.kind == LobeKind::Conductor) {
    constexpr double kSchlickAt82 = 0.46266436;  // (1 - 1/7)^5
    constexpr double kB = 17.651384;             // 1 / (1/7 (1 - 1/7)^6)
    const Color b = glm::mix(color, Color(1.0), kSchlickAt82) * (Color(1.0) - l.tint) * kB;
    return glm::clamp(glm::mix(color, Color(1.0), 1.0 / 21.0) - b / 126.0, 0.0, 1.0);
  }
  const double eta = l.ior >= 1.0 ? l.ior : 1.0 / l.ior;
  const double real = (eta - 1.0) / (4.08567 + 1.00071 * eta);
  const double f0 = (eta - 1.0) * (eta - 1.0) / ((eta + 1.0) * (eta + 1.0));
  if (!l.tint_f0) return l.tint * real;
  const double s = glm::clamp((real - f0) / (1.0 - f0), 0.0, 1.0);
  return glm::mix(l.tint * f0, Color(1.0), s);
}

// Linear interpolation in a table of `steps` entries over [0, 1].
double lerp_table(const float* table, int steps, double x) {
  x = glm::clamp(x, 0.0, 1.0) * (steps - 1);
  const int i = std::min(static_cast<int>(x), steps - 2);
  const double t = x - i;
  return (1.0 - t) * table[i] + t * table[i + 1];
}

// A tabulated quantity of a lobe by roughness: `rows` rows (one for a constant roughness, else
// kLayerRoughnessSteps over [0, 1]) of `stride` floats, interpolated between the two rows around
// this point's roughness by `read` (a row's value).
template <class Read>
double by_roughness(const Lobe& lobe, const SurfacePoint& sp, const float* rows, int stride, Read&& read) {
  if (!lobe.roughness_input.used()) return read(rows);
  const double y = lobe.roughness_at(sp) * (kLayerRoughnessSteps - 1);
  const int j = std::min(static_cast<int>(y), kLayerRoughnessSteps - 2);
  const double t = y - j;
  return (1.0 - t) * read(rows + j * stride) + t * read(rows + (j + 1) * stride);
}

int roughness_rows(const Lobe& lobe) { return lobe.roughness_input.used() ? kLayerRoughnessSteps : 1; }

// A multiscatter glass's single-scattering albedo towards `view`, and its average (Lobe::glass_energy).
void glass_energy(const Lobe& l, const SurfacePoint& sp, const Vec3& view, double mu, double& e, double& e_avg) {
  constexpr int kStride = kGlassEnergySteps + 1;
  const bool inside = glm::dot(view, sp.ng) < 0.0;  // as the dielectric's own side
  const float* side = l.glass_energy.data() + (inside ? roughness_rows(l) * kStride : 0);
  e = by_roughness(l, sp, side, kStride, [mu](const float* row) { return lerp_table(row, kGlassEnergySteps, mu); });
  e_avg = by_roughness(l, sp, side, kStride,
                       [](const float* row) { return static_cast<double>(row[kGlassEnergySteps]); });
}

// Multiscatter GGX (Cycles, after Kulla and Conty): single scattering times 1 + Fms (1 - E) / E,
// towards `view`. Glass takes E over reflection and refraction from its own table, and its
// refraction tint as Fss, as Cycles does (measured in 5.0: a tinted Principled glass of roughness
// 0.8 is 9% too bright with Fss = 1).
Color multiscatter_factor(const Lobe& l, const SurfacePoint& sp, const Vec3& view) {
  if (!l.multiscatter || !l.microfacet()) return Color(1.0);  // (a rough diffuse lobe has its own)
  const double roughness = l.roughness_at(sp);
  if (roughness < kSmoothRoughness) return Color(1.0);
  const double mu = glm::clamp(std::fabs(glm::dot(view, sp.ns)), 0.0, 1.0);
  double e = 1.0, e_avg = 1.0;
  Color fss(1.0);
  if (l.glass()) {
    glass_energy(l, sp, view, mu, e, e_avg);
    fss = glm::clamp(l.color_at(sp), 0.0, 1.0);
  } else {
    e = ggx_albedo(roughness, mu);
    e_avg = ggx_average_albedo(roughness);
    fss = average_fresnel(l, sp);
  }
  e = std::fmax(e, 1e-3);
  const Color fms = fss * e_avg / (Color(1.0) - fss * (1.0 - e_avg));
  return Color(1.0) + fms * ((1.0 - e) / e);
}

double layer_albedo(const Lobe& lobe, const SurfacePoint& sp, double mu) {
  return by_roughness(lobe, sp, lobe.albedo.data(), kLayerAlbedoSteps,
                      [mu](const float* row) { return lerp_table(row, kLayerAlbedoSteps, mu); });
}

// Each lobe's weight towards `view`: its own weight, its multiple scattering, and the layers above.
void effective_weights(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& view, Color eff[]) {
  const double mu = glm::clamp(std::fabs(glm::dot(view, sp.ns)), 0.0, 1.0);
  double cover = 1.0;
  for (size_t i = 0; i < lobes.size(); ++i) {
    eff[i] = lobes[i].weight_at(sp) * cover * multiscatter_factor(lobes[i], sp, view);
    if (lobes[i].layer) cover *= glm::clamp(1.0 - layer_albedo(lobes[i], sp, mu), 0.0, 1.0);
  }
}

// A rough guess of how much of the light a lobe scatters towards the viewer, for picking lobes.
double albedo_guess(const Lobe& lobe, const SurfacePoint& sp, const Vec3& wo) {
  const Color color = lobe.color_at(sp);
  if (lobe.kind != LobeKind::Dielectric) return luminance(color);
  if (lobe.parts == kReflectionAndRefraction) return 0.5 * (luminance(lobe.tint) + luminance(color));
  const double mu = std::fabs(glm::dot(wo, sp.ns));
  const bool inside = lobe.parts != kReflection && glm::dot(wo, sp.ng) < 0.0;  // as dielectric_side
  const double F = inside ? fresnel_dielectric(mu, lobe.ior, 1.0) : fresnel_dielectric(mu, 1.0, lobe.ior);
  return lobe.parts == kReflection ? luminance(lobe.tint) * std::fmax(F, 0.02) : luminance(color);
}

// Picking probabilities over the lobes `use` selects; returns their sum before normalising.
template <class Use>
double pick_probabilities(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, const Color eff[],
                          Use&& use, double prob[]) {
  double total = 0.0;
  for (size_t i = 0; i < lobes.size(); ++i) {
    prob[i] = use(lobes[i]) ? std::fmax(luminance(eff[i]), 0.0) * albedo_guess(lobes[i], sp, wo) : 0.0;
    total += prob[i];
  }
  if (total > 0.0)
    for (size_t i = 0; i < lobes.size(); ++i) prob[i] /= total;
  return total;
}

int pick(const std::vector<Lobe>& lobes, const double prob[], double u) {
  double sum = 0.0;
  int last = -1;
  for (size_t i = 0; i < lobes.size(); ++i) {
    if (prob[i] <= 0.0) continue;
    last = static_cast<int>(i);
    sum += prob[i];
    if (u < sum) return last;
  }
  return last;  // rounding left u past the sum
}

// A conductor or glossy lobe's parameters at a point: its tangent turned by its rotation about the
// shading normal (as Cycles turns it, about the unflipped normal).
ConductorParams conductor_at(const Lobe& l, const SurfacePoint& sp, const Color& color) {
  ConductorParams p{color, l.tint, l.roughness_at(sp), l.kind == LobeKind::Glossy};
  p.beckmann = l.beckmann;
  if (!l.anisotropic() || sp.tangent == Vec3(0.0)) return p;
  p.stretch_x = l.stretch_x;
  p.stretch_y = l.stretch_y;
  p.tangent = sp.tangent;
  if (l.rotation != 0.0) {  // Rodrigues' rotation about ns
    const double angle = 2.0 * kPi * l.rotation, c = std::cos(angle), s = std::sin(angle);
    const Vec3& k = sp.ns;
    p.tangent = p.tangent * c + glm::cross(k, p.tangent) * s + k * glm::dot(k, p.tangent) * (1.0 - c);
  }
  return p;
}

Color lobe_eval(const Lobe& l, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  const Color color = l.color_at(sp);
  switch (l.kind) {
    case LobeKind::Diffuse: {
      const double sigma = l.roughness_at(sp);
      if (sigma > 0.0) return oren_nayar_eval({color, sigma, l.multiscatter}, sp, wo, wi);
      return lambert_eval(color, sp, wo, wi, false);
    }
    case LobeKind::Translucent: return lambert_eval(color, sp, wo, wi, true);
    case LobeKind::Transparent: return Color(0.0);
    case LobeKind::Conductor:
    case LobeKind::Glossy: return conductor_eval(conductor_at(l, sp, color), sp, wo, wi);
    case LobeKind::Dielectric: return dielectric_eval(l.dielectric(sp), sp, wo, wi);
    case LobeKind::Velvet: return velvet_eval(color, l.roughness_at(sp), sp, wo, wi);
    case LobeKind::SchlickSheen: return schlick_sheen_eval(color, sp, wo, wi);
    case LobeKind::MicrofiberSheen: return microfiber_sheen_eval(color, l.roughness_at(sp), sp, wo, wi);
  }
  return Color(0.0);
}

bool lobe_sample(const Lobe& l, const SurfacePoint& sp, const Vec3& wo, double u1, double u2, double u3, bool photon,
                 BsdfSample& out) {
  const Color color = l.color_at(sp);
  switch (l.kind) {
    case LobeKind::Diffuse: {
      const double sigma = l.roughness_at(sp);
      if (sigma > 0.0) return oren_nayar_sample({color, sigma, l.multiscatter}, sp, wo, u1, u2, out);
      return lambert_sample(color, sp, wo, u1, u2, false, out);
    }
    case LobeKind::Translucent: return lambert_sample(color, sp, wo, u1, u2, true, out);
    case LobeKind::Transparent: out = BsdfSample{-wo, color, true, 0}; return true;
    case LobeKind::Conductor:
    case LobeKind::Glossy: return conductor_sample(conductor_at(l, sp, color), sp, wo, u1, u2, out);
    case LobeKind::Dielectric: return dielectric_sample(l.dielectric(sp), sp, wo, u1, u2, u3, photon, out);
    case LobeKind::Velvet: return velvet_sample(color, l.roughness_at(sp), sp, wo, u1, u2, out);
    case LobeKind::SchlickSheen: return schlick_sheen_sample(color, sp, wo, u1, u2, out);
    case LobeKind::MicrofiberSheen:
      return microfiber_sheen_sample(color, l.roughness_at(sp), sp, wo, u1, u2, photon, out);
  }
  return false;
}

// One row of a layer's albedo table: by cos(theta), at the lobe's own (constant) roughness.
void tabulate_layer_albedo(const Lobe& lobe, float* row) {
  constexpr int kSide = 32;  // stratified samples per axis
  const SurfacePoint flat{Vec3(0, 0, 1), Vec3(0, 0, 1), Color(1.0)};
  for (int m = 0; m < kLayerAlbedoSteps; ++m) {
    const double mu = std::max(static_cast<double>(m) / (kLayerAlbedoSteps - 1), 1e-3);
    const Vec3 wo(std::sqrt(1.0 - mu * mu), 0.0, mu);
    double sum = 0.0;
    for (int i = 0; i < kSide; ++i)
      for (int j = 0; j < kSide; ++j) {
        BsdfSample s;
        if (lobe_sample(lobe, flat, wo, (i + 0.5) / kSide, (j + 0.5) / kSide, 0.5, false, s))
          sum += max_component(s.weight);
      }
    const Color ms = multiscatter_factor(lobe, flat, wo);
    row[m] = static_cast<float>(sum / (kSide * kSide) * max_component(ms));
  }
}

// Cycles' bump shadowing where a normal map tilted the normal (SurfacePoint::smooth_normal; the
// kinds in scatter.h's BumpSoftening): diffuse lobes lose light towards the smooth normal's terminator,
// and, in the newer form, light from the far side of the smooth normal is refused (for every lobe
// when `evaluated`, for diffuse ones when sampled). `view` is on the viewer's side, `light`
// towards the light.
double bump_shadowing(const Lobe& l, const SurfacePoint& sp, const Vec3& view, const Vec3& light, bool evaluated) {
  if (sp.softening == BumpSoftening::None || sp.smooth_normal == Vec3(0.0) || sp.smooth_normal == sp.ns) return 1.0;
  const double side = glm::dot(view, sp.ng) >= 0.0 ? 1.0 : -1.0;
  const Vec3 smooth = side * sp.smooth_normal, n = side * sp.ns;
  const bool diffuse = l.diffuse();
  if (sp.softening == BumpSoftening::Chiang) {
    if (!diffuse) return 1.0;
    const Vec3 s = l.kind == LobeKind::Translucent ? -smooth : smooth;
    const double denominator = glm::dot(n, light) * glm::dot(s, n);
    const double g = denominator != 0.0 ? glm::dot(s, light) / denominator : 0.0;
    if (g >= 1.0) return 1.0;
    if (g < 0.0) return 0.0;
    return g * (1.0 + g - g * g);  // smooth at g = 1
  }
  const double cos_si = glm::dot(smooth, light), cos_sn = glm::dot(smooth, n), cos_ni = glm::dot(n, light);
  if (cos_si * cos_sn * cos_ni < 0.0 && (evaluated || diffuse)) return 0.0;
  if (!diffuse) return 1.0;
  const double cos_i = std::fabs(cos_si), cos_d = std::fabs(cos_sn);
  if (cos_d >= 1.0 || cos_i >= 1.0) return 1.0;
  if (cos_i < 1e-6) return 0.0;
  const double bump_a2 = glm::clamp(0.125 * (1.0 / (cos_d * cos_d) - 1.0), 0.0, 1.0);
  return ggx_g1(Vec3(std::sqrt(1.0 - cos_i * cos_i), 0.0, cos_i), bump_a2);
}

// One row of a multiscatter glass's energy table on one side (Lobe::glass_energy), at the lobe's
// own (constant) roughness: white reflection plus refraction as the eye side samples it.
void tabulate_glass_energy(const Lobe& lobe, bool inside, float* row) {
  constexpr int kSide = 64;  // stratified samples per axis; the branch picked quasi-randomly
  const SurfacePoint flat{Vec3(0, 0, 1), Vec3(0, 0, 1), Color(1.0)};
  const DielectricParams p{lobe.ior, lobe.roughness, Color(1.0), Color(1.0), kReflectionAndRefraction, false};
  double average = 0.0;
  for (int m = 0; m < kGlassEnergySteps; ++m) {
    const double mu = std::max(static_cast<double>(m) / (kGlassEnergySteps - 1), 1e-3);
    const Vec3 wo(std::sqrt(1.0 - mu * mu), 0.0, inside ? -mu : mu);
    double sum = 0.0;
    for (int i = 0; i < kSide; ++i)
      for (int j = 0; j < kSide; ++j) {
        BsdfSample s;
        const double u3 = std::fmod((i * kSide + j) * 0.6180339887498949, 1.0);
        if (dielectric_sample(p, flat, wo, (i + 0.5) / kSide, (j + 0.5) / kSide, u3, false, s)) sum += s.weight.x;
      }
    row[m] = static_cast<float>(sum / (kSide * kSide));
    average += 2.0 * mu * row[m] * (m == 0 || m == kGlassEnergySteps - 1 ? 0.5 : 1.0) / (kGlassEnergySteps - 1);
  }
  row[kGlassEnergySteps] = static_cast<float>(average);
}

void prepare_glass_energy(Lobe& lobe) {
  constexpr int kStride = kGlassEnergySteps + 1;
  const int rows = roughness_rows(lobe);
  lobe.glass_energy.resize(2 * rows * kStride);
  Lobe fixed = lobe;
  fixed.roughness_input = InputRef{};
  for (int side = 0; side < 2; ++side)
    for (int j = 0; j < rows; ++j) {
      if (rows > 1) fixed.roughness = static_cast<double>(j) / (rows - 1);
      tabulate_glass_energy(fixed, side == 1, lobe.glass_energy.data() + (side * rows + j) * kStride);
    }
}

}  // namespace

void prepare_lobe(Lobe& lobe) {
  lobe.albedo.clear();
  lobe.glass_energy.clear();
  if (lobe.multiscatter && lobe.glass()) prepare_glass_energy(lobe);
  if (!lobe.layer) return;
  if (!lobe.roughness_input.used()) {
    lobe.albedo.resize(kLayerAlbedoSteps);
    tabulate_layer_albedo(lobe, lobe.albedo.data());
    return;
  }
  // A textured roughness: rows at roughness 0, 1/16, ..., 1 (the texture's value times the lobe's).
  lobe.albedo.resize(kLayerAlbedoSteps * kLayerRoughnessSteps);
  Lobe fixed = lobe;
  fixed.roughness_input = InputRef{};
  for (int j = 0; j < kLayerRoughnessSteps; ++j) {
    fixed.roughness = static_cast<double>(j) / (kLayerRoughnessSteps - 1);
    tabulate_layer_albedo(fixed, lobe.albedo.data() + j * kLayerAlbedoSteps);
  }
}

Color closure_eval(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  Color eff[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  Color f(0.0);
  for (size_t i = 0; i < lobes.size(); ++i)
    if (!lobes[i].followed(sp)) f += eff[i] * lobe_eval(lobes[i], sp, wo, wi) * bump_shadowing(lobes[i], sp, wo, wi, true);
  return f;
}

Color closure_eval_followed_rough(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo,
                                  const Vec3& wi) {
  Color eff[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  Color f(0.0);
  for (size_t i = 0; i < lobes.size(); ++i) {
    const Lobe& l = lobes[i];
    if (l.followed(sp) && !l.delta_at(l.roughness_at(sp)))
      f += eff[i] * lobe_eval(l, sp, wo, wi) * bump_shadowing(l, sp, wo, wi, true);
  }
  return f;
}

double closure_followed_pdf(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, const Vec3& wi) {
  Color eff[kMaxLobes];
  double prob[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  if (!(pick_probabilities(lobes, sp, wo, eff, [&sp](const Lobe& l) { return l.followed(sp); }, prob) > 0.0))
    return 0.0;
  double pdf = 0.0;
  for (size_t i = 0; i < lobes.size(); ++i) {
    const Lobe& l = lobes[i];
    if (prob[i] <= 0.0 || l.delta_at(l.roughness_at(sp))) continue;
    if (l.kind == LobeKind::Dielectric)
      pdf += prob[i] * dielectric_pdf(l.dielectric(sp), sp, wo, wi);
    else if (l.kind == LobeKind::Conductor || l.kind == LobeKind::Glossy)
      pdf += prob[i] * conductor_pdf(conductor_at(l, sp, l.color_at(sp)), sp, wo, wi);
  }
  return pdf;
}

bool closure_has_rough_followed(const std::vector<Lobe>& lobes, const SurfacePoint& sp) {
  for (const Lobe& l : lobes)
    if (l.followed(sp) && !l.delta_at(l.roughness_at(sp))) return true;
  return false;
}

bool closure_lambertian(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, Color& albedo) {
  if (sp.softening != BumpSoftening::None && sp.smooth_normal != Vec3(0.0) && sp.smooth_normal != sp.ns) return false;
  Color eff[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  albedo = Color(0.0);
  for (size_t i = 0; i < lobes.size(); ++i) {
    const Lobe& l = lobes[i];
    if (l.followed(sp)) continue;
    if (l.kind != LobeKind::Diffuse || l.roughness_at(sp) > 0.0) return false;
    albedo += eff[i] * l.color_at(sp);
  }
  return true;
}

ClassColors closure_eval_classes(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo,
                                 const Vec3& wi) {
  Color eff[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  const bool reflected = glm::dot(wo, sp.ng) * glm::dot(wi, sp.ng) > 0.0;
  ClassColors f;
  for (size_t i = 0; i < lobes.size(); ++i) {
    const Lobe& l = lobes[i];
    if (l.followed(sp)) continue;
    const int c = l.diffuse() || l.sheen() ? kDiffuseClass : reflected ? kGlossyClass : kTransmissionClass;
    f.c[c] += eff[i] * lobe_eval(l, sp, wo, wi) * bump_shadowing(l, sp, wo, wi, true);
  }
  return f;
}

bool closure_sample(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, double u_pick,
                    double u1, double u2, double u3, bool adjoint, BsdfSample& out) {
  Color eff[kMaxLobes];
  double prob[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  if (!(pick_probabilities(lobes, sp, wo, eff, [](const Lobe&) { return true; }, prob) > 0.0)) return false;
  const int i = pick(lobes, prob, u_pick);
  if (i < 0 || !lobe_sample(lobes[i], sp, wo, u1, u2, u3, adjoint, out)) return false;
  if (adjoint) effective_weights(lobes, sp, out.wi, eff);
  // A photon's light comes from wo; an eye path's from the sampled direction.
  out.weight *= eff[i] / prob[i] *
                (adjoint ? bump_shadowing(lobes[i], sp, out.wi, wo, false) : bump_shadowing(lobes[i], sp, wo, out.wi, false));
  return true;
}

namespace {

// A lobe's Denoising Albedo towards wo (cos theta `mu`): its colour (a dielectric's reflection by its
// tint and its Fresnel reflectance, its refraction by its colour and the rest), a layer's by its
// tabulated albedo.
Color lobe_albedo(const Lobe& l, const SurfacePoint& sp, const Vec3& wo, double mu) {
  if (l.kind != LobeKind::Dielectric) return l.color_at(sp) * (l.layer ? layer_albedo(l, sp, mu) : 1.0);
  const double F = glm::dot(wo, sp.ng) < 0.0 ? fresnel_dielectric(mu, l.ior, 1.0) : fresnel_dielectric(mu, 1.0, l.ior);
  Color albedo(0.0);
  if (l.parts & kReflection) albedo += l.tint * (l.layer ? layer_albedo(l, sp, mu) : F);
  if (l.parts & kRefraction) albedo += l.color_at(sp) * (l.parts == kRefraction ? 1.0 : 1.0 - F);
  return albedo;
}

// The sum of lobe_albedo over the lobes `select` takes, each times its weight after the layers above.
template <class Select>
Color albedo_of(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, Select&& select) {
  Color eff[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  const double mu = glm::clamp(std::fabs(glm::dot(wo, sp.ns)), 0.0, 1.0);
  Color albedo(0.0);
  for (size_t i = 0; i < lobes.size(); ++i)
    if (select(lobes[i])) albedo += eff[i] * lobe_albedo(lobes[i], sp, wo, mu);
  return albedo;
}

}  // namespace

Color closure_albedo(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo) {
  return albedo_of(lobes, sp, wo, [&sp](const Lobe& l) { return !l.followed(sp); });
}

Color closure_followed_albedo(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo) {
  return albedo_of(lobes, sp, wo, [&sp](const Lobe& l) { return l.followed(sp) && l.rough_for_denoising(sp); });
}

ClassColors closure_class_albedo(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo) {
  Color eff[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  const double mu = glm::clamp(std::fabs(glm::dot(wo, sp.ns)), 0.0, 1.0);
  ClassColors albedo;
  for (size_t i = 0; i < lobes.size(); ++i) {
    const Lobe& l = lobes[i];
    if (l.kind == LobeKind::Transparent) continue;
    if (l.diffuse() || l.sheen()) {
      albedo.c[kDiffuseClass] += eff[i] * l.color_at(sp);
      continue;
    }
    if (l.kind != LobeKind::Dielectric) {
      albedo.c[kGlossyClass] += eff[i] * l.color_at(sp) * (l.layer ? layer_albedo(l, sp, mu) : 1.0);
      continue;
    }
    const bool inside = glm::dot(wo, sp.ng) < 0.0;
    const double F = inside ? fresnel_dielectric(mu, l.ior, 1.0) : fresnel_dielectric(mu, 1.0, l.ior);
    if (l.parts & kReflection) albedo.c[kGlossyClass] += eff[i] * l.tint * (l.layer ? layer_albedo(l, sp, mu) : F);
    if (l.parts & kRefraction)
      albedo.c[kTransmissionClass] += eff[i] * l.color_at(sp) * (l.parts == kRefraction ? 1.0 : 1.0 - F);
  }
  return albedo;
}

double closure_followed_share(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo) {
  Color eff[kMaxLobes];
  double prob[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  if (!(pick_probabilities(lobes, sp, wo, eff, [](const Lobe&) { return true; }, prob) > 0.0)) return 0.0;
  double share = 0.0;
  for (size_t i = 0; i < lobes.size(); ++i)
    if (lobes[i].followed(sp)) share += prob[i];
  return glm::clamp(share, 0.0, 1.0);
}

int closure_followed_branches(const std::vector<Lobe>& lobes, const SurfacePoint& sp, const Vec3& wo, double u,
                              double u1, double u2, double u3, BsdfSample out[2]) {
  Color eff[kMaxLobes];
  double prob[kMaxLobes];
  effective_weights(lobes, sp, wo, eff);
  if (!(pick_probabilities(lobes, sp, wo, eff, [&sp](const Lobe& l) { return l.followed(sp); }, prob) > 0.0))
    return 0;
  const int i = pick(lobes, prob, u);
  if (i < 0) return 0;
  const Lobe& l = lobes[i];
  int count = 0;
  if (l.kind == LobeKind::Dielectric && l.delta_at(l.roughness_at(sp))) {
    count = dielectric_branches(l.dielectric(sp), sp, wo, false, out);
  } else {
    count = lobe_sample(l, sp, wo, u1, u2, u3, false, out[0]) ? 1 : 0;
  }
  for (int b = 0; b < count; ++b) {
    out[b].weight *= eff[i] / prob[i];
    out[b].lobe = static_cast<int8_t>(i);
  }
  return count;
}

bool closure_has_followed(const std::vector<Lobe>& lobes) {
  for (const Lobe& l : lobes)
    if (l.may_be_followed()) return true;
  return false;
}

bool closure_is_followed(const std::vector<Lobe>& lobes) {
  for (const Lobe& l : lobes)
    if (!l.always_followed()) return false;
  return !lobes.empty();
}

bool closure_transmits(const std::vector<Lobe>& lobes) {
  for (const Lobe& l : lobes)
    if (l.kind == LobeKind::Translucent) return true;  // (refraction is followed)
  return false;
}

}  // namespace ppm
