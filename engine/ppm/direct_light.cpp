// Direct light at hit points (see direct_light.h).
#include "ppm/direct_light.h"

#include "math/rng.h"
#include "base/parallel.h"

namespace ppm {
namespace {

constexpr uint64_t kDirectStream = 1ull << 40;
constexpr uint64_t kVolumeDirectStream = 3ull << 40;
constexpr size_t kChunk = 4096;

// One light sample's contribution to a hit point; with `classes`, added there split by class of lobe
// as well, times `scale`.
Color light_contribution(const Scene& scene, const Light& light, const HitPoint& hp, const HitPointShading& sh,
                         double u1, double u2, int strategy, double scale, ClassColors* classes,
                         const MediumStack* media, Rng& rng) {
  const Vec3 n(hp.normal);
  DirectSample ds;
  if (!sample_direct(light, hp.position, n, u1, u2, ds, strategy)) return Color(0.0);
  const Material& m = scene.material(sh.material);
  const SurfacePoint sp = scene.surface_point(surface_record(hp, sh));
  ClassColors split;
  if (classes) split = bsdf_eval_classes(m, sp, Vec3(sh.wo), ds.wi);
  const Color f = classes ? split.total() : bsdf_eval(m, sp, Vec3(sh.wo), ds.wi);
  const double cos = std::fabs(glm::dot(Vec3(sh.shading_normal), ds.wi));
  Color c = Color(sh.throughput) * f * (cos * ds.value);
  if (!(max_component(c) > 0.0)) return Color(0.0);
  const Vec3 origin = offset_point(hp.position, sh.geometric_normal, ds.wi, scene.offset_floor());
  const double dist = shadow_distance(hp.position, ds, scene.offset_floor());  // short of an emitter's own surface
  if (!(dist > 0.0)) return Color(0.0);
  Color tr(1.0);  // through media (scenes with media only): their transmittance to the light
  if (light.cast_shadow) {
    if (media == nullptr) {
      if (scene.occluded(Ray{origin, ds.wi, kShadowRay}, dist)) return Color(0.0);
    } else {
      tr = scene.shadow_transmittance(Ray{origin, ds.wi, kShadowRay}, dist, *media, rng);
      if (!(max_component(tr) > 0.0)) return Color(0.0);
      c *= tr;
    }
  }
  if (classes)
    for (int k = 0; k < kLightClasses; ++k)
      classes->c[k] += Color(sh.throughput) * split.c[k] * tr * (cos * ds.value * scale);
  return c;
}

// One light sample at a hit point in a medium: the phase function instead of a BSDF and no cosine,
// `sigma_s` (the medium's there) times the hit point's weight (VolumeHitPoint), the transmittance
// to the light (`rng`: through media that vary). `n` is a
// direction the light's sampling takes as a surface normal: sample_direct covers the hemisphere
// about it for the world (cosine and environment strategies), so the world is sampled about n and
// -n (volume_light_sample's caller), every other light in full.
Color volume_light_sample(const Scene& scene, const Light& light, const VolumeHitPoint& h, const Medium& med,
                          const Color& sigma_s, const Vec3& n, double u1, double u2, int strategy, Rng& rng) {
  DirectSample ds;
  if (!sample_direct(light, h.position, n, u1, u2, ds, strategy)) return Color(0.0);
  // Light travels along -wi into the point and leaves back along the eye path, -direction.
  const double phase = med.c.phase.eval(-ds.wi, -Vec3(h.direction));
  Color c = Color(h.weight) * sigma_s * (phase * ds.value);
  if (!(max_component(c) > 0.0)) return Color(0.0);
  const double dist = shadow_distance(h.position, ds, scene.offset_floor());
  if (!(dist > 0.0)) return Color(0.0);
  if (light.cast_shadow) c *= scene.shadow_transmittance(Ray{h.position, ds.wi, kShadowRay}, dist, h.media, rng);
  return c;
}

}  // namespace

bool volume_direct_light_pass(const Scene& scene, const LightSampler& lights, const Settings& settings, uint64_t pass,
                              int threads, std::vector<VolumeHitPoint>& points, std::atomic<bool>& cancel,
                              const std::function<bool()>& poll, uint64_t first_index) {
  const size_t n = points.size(), chunks = (n + kChunk - 1) / kChunk;
  auto work = [&](int, size_t chunk) {
    for (size_t i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) {
      VolumeHitPoint& h = points[i];
      Rng rng(settings.seed, kVolumeDirectStream + pass, first_index + i);
      const Medium& med = scene.medium(static_cast<uint32_t>(h.medium));
      const Vec3 axis(h.direction);
      const Color sigma_s = scene.sigma_s_at(med, h.position, axis);
      Color sum(0.0);
      for (uint32_t l : lights.analytic()) {
        const Light& light = scene.lights()[l];
        const bool world = light.kind == LightKind::Background;
        for (int side = 0; side < (world ? 2 : 1); ++side)
          for (int strategy = 0; strategy < direct_samples(light); ++strategy) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            sum += volume_light_sample(scene, light, h, med, sigma_s, side ? -axis : axis, u1, u2, strategy, rng);
          }
      }
      if (lights.has_triangles()) {
        double pdf;
        const uint32_t l = lights.pick_triangle(rng.uniform(), pdf);
        const double u1 = rng.uniform(), u2 = rng.uniform();
        sum += volume_light_sample(scene, scene.lights()[l], h, med, sigma_s, axis, u1, u2, 0, rng) / pdf;
      }
      h.direct = Vec3f(sum);
    }
  };
  return parallel_chunks(threads, chunks, work, cancel, poll, settings.progress_interval);
}

bool direct_light_pass(const Scene& scene, const LightSampler& lights, const Settings& settings,
                       uint64_t pass, int threads, HitPoints& hp, DirectScratch& scratch,
                       std::atomic<bool>& cancel, const std::function<bool()>& poll, uint64_t first_index) {
  const size_t n = hp.size(), chunks = (n + kChunk - 1) / kChunk;
  const bool split = !hp.components.empty();
  std::vector<Color>& sums = scratch.sums;
  sums.resize(n);  // every entry is written below before any is added
  scratch.classes.resize(split ? n : 0);
  const BounceLimits limits = BounceLimits::of(settings, scene);
  auto work = [&](int, size_t chunk) {
    for (size_t i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) {
      Rng rng(settings.seed, kDirectStream + pass, first_index + i);
      const int depth = limits.active ? hp.chain[i].total : 0;  // the eye chain's scatterings
      Color sum(0.0);
      ClassColors* classes = split ? &scratch.classes[i] : nullptr;
      const MediumStack* media = hp.media.empty() ? nullptr : &hp.media[i];
      if (classes) *classes = ClassColors{};
      for (uint32_t l : lights.analytic()) {
        const Light& light = scene.lights()[l];
        for (int strategy = 0; strategy < direct_samples(light); ++strategy) {
          const double u1 = rng.uniform(), u2 = rng.uniform();
          if (depth > light.max_bounces) continue;  // its own Max Bounces (the numbers are drawn all the same)
          sum += light_contribution(scene, light, hp.points[i], hp.shading[i], u1, u2, strategy, 1.0, classes, media,
                                    rng);
        }
      }
      if (lights.has_triangles()) {
        double pdf;
        const uint32_t l = lights.pick_triangle(rng.uniform(), pdf);
        const double u1 = rng.uniform(), u2 = rng.uniform();
        sum += light_contribution(scene, scene.lights()[l], hp.points[i], hp.shading[i], u1, u2, 0, 1.0 / pdf, classes,
                                  media, rng) /
               pdf;
      }
      sums[i] = sum;
    }
  };
  if (!parallel_chunks(threads, chunks, work, cancel, poll, settings.progress_interval)) return false;
  parallel_for(threads, n, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      hp.stats[i].direct += sums[i];
      if (split)
        for (int k = 0; k < kLightClasses; ++k) hp.components[i].direct[k] += Vec3f(scratch.classes[i].c[k]);
    }
  });
  return true;
}

}  // namespace ppm
