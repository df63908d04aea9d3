// Eye pass (see eye_pass.h).
#include "ppm/eye_pass.h"

#include "math/rng.h"
#include "ppm/denoising_features.h"
#include "base/freed_memory.h"
#include "base/parallel.h"

#include <algorithm>
#include <type_traits>
#include <cmath>
#include <limits>

namespace ppm {
namespace {

constexpr uint64_t kEyeStream = 1;
constexpr int kSplitDepth = 3;      // glass interfaces split into both branches up to this depth
// A path split in a medium (split_path) goes on for sure where it keeps at least this much.
constexpr double kSplitRoulette = 0.1;
constexpr int kRowsPerChunk = 2;

struct EyeVertex {
  Ray ray;
  Color throughput;
  int depth;
  double length;    // distance travelled, for the pixel footprint
  bool glass_only;  // every interface so far refracted through smooth glass (or none: a camera ray)
  Bounces chain;    // its scatterings by kind (depth is their total)
  // Past a bounce limit: the ray still sees lights, emission and the world, as in Cycles (a limit
  // stops the path after the next surface's emission), but records no hit point and goes no further.
  bool emission_only;
  // The chance that a single path (Cycles', which picks one branch where we split) comes this way:
  // what the denoising normal is weighted by.
  double share = 1.0;
  uint8_t route = kNoBounce;  // the class of its chain's first bounce (light_components.h)
  // Drawn from a rough lobe the eye follows, where lights were sampled too (sample_lights): the
  // density of its direction, which weighs the lights it meets against that sampling; 0: none.
  double mis_pdf = 0.0;
  // Its denoising features were written at a rough lobe it followed (Lobe::rough_for_denoising).
  bool features_done = false;
};

// Scenes with media: what an eye vertex knows of them, kept in an array beside the vertices' (so
// that scenes without media copy and initialise the vertices they did before).
struct EyeMedia {
  MediumStack stack;       // the media it is in (scene/medium.h)
  uint16_t crossings = 0;  // boundaries without a surface crossed (kMaxMediumCrossings)
};

// The route after a bounce that sent a ray of `kind` from a vertex on `route`.
uint8_t route_after(uint8_t route, uint8_t kind) {
  if (route != kNoBounce) return route;
  return kind == kTransmissionRay ? kTransmissionClass : kind == kGlossyRay ? kGlossyClass : kDiffuseClass;
}

// Files the emission a vertex past its chain's first bounce sees (what `emitted` gained while it
// lived) into its route's Direct (after one bounce) or Indirect component.
struct FileEmission {
  ComponentLight* out;
  const EyeVertex& v;
  const Color& emitted;
  Color start;
  ~FileEmission() {
    if (out && v.depth > 0) out->light[emission_component(v.route, v.depth)] += Vec3f(emitted - start);
  }
  // Light the vertex adds to `emitted` that belongs to another component (`k`), filed there instead.
  void file_apart(const Color& light, LightComponent k) {
    start += light;
    if (out) out->light[k] += Vec3f(light);
  }
};

using ChunkOutput = EyePassScratch::Chunk;

// One eye sample's denoising features (denoising_features.h): the albedo its hit points see
// through their throughput, and their normals weighted by the chance a single path reaches them.
struct SampleFeatures {
  Color albedo{0.0};
  Vec3 normal{0.0};
  void add(const Color& throughput, const Color& surface_albedo, const Vec3& n, double share) {
    albedo += throughput * surface_albedo;
    normal += share * n;
  }
};

struct EyeTracer {
  const Scene& scene;
  const Settings& settings;
  const EyePassOptions& options;
  std::vector<uint32_t> visible_lights;  // lights with a surface: spheres (spots too), rectangles, disks
  std::vector<uint32_t> visible_suns;    // suns of a non-zero angle: a disc in the sky
  std::vector<uint32_t> delta_lights;    // points, spots without a radius, suns of no angle
  std::vector<uint32_t> pdf_lights;      // light_has_pdf: sampled with multiple importance sampling
  const Light* background;  // what rays that escape see (nullptr: black)
  double footprint;
  bool orthographic;
  BounceLimits limits;
  bool media = false;  // the scene has media: every ray segment takes a medium step

  // A light's own Max Bounces: does it reach a path that has scattered `depth` times?
  static bool reaches(const Light& light, int depth) { return depth <= light.max_bounces; }

  // The share of light `l` met along v's ray that v's own sampling carries (the balance
  // heuristic against light sampling at the vertex it left: sample_lights); 1 where that sampled
  // no light.
  double bsdf_share(const EyeVertex& v, const Light& l) const {
    if (!(v.mis_pdf > 0.0) || !light_has_pdf(l)) return 1.0;
    if (settings.followed_light == FollowedLight::Lights) return 0.0;
    return v.mis_pdf / (v.mis_pdf + light_pdf(l, v.ray.origin, v.ray.direction));
  }

  // Does this vertex's path make the pixel transparent where it escapes or meets a holdout?
  // Cycles: camera rays, and with transparent glass those refracted through glass only.
  bool transparent_path(const EyeVertex& v) const {
    return v.depth == 0 || (settings.transparent_glass && v.glass_only);
  }

  // Adds the radiance of the suns whose disc an escaping ray points into (Cycles shows a sun to
  // glossy and transmission rays, and to camera rays if it is visible to them).
  void see_suns(const EyeVertex& v, Color& emitted) const {
    for (uint32_t i : visible_suns) {
      const Light& sun = scene.lights()[i];
      if ((sun.visibility & v.ray.kind) && reaches(sun, v.depth) &&
          -glm::dot(v.ray.direction, sun.direction) >= sun.cos_sun)
        emitted += v.throughput * sun.radiance * bsdf_share(v, sun);
    }
  }

  // A path that leaves the scene: transparent, or what it sees of the suns and the background.
  // `seen`: where a camera ray's (no bounce) sun and world go too, or nullptr.
  void escape(const EyeVertex& v, Color& emitted, double& transparency, SeenLight* seen) const {
    if (settings.transparent_background && transparent_path(v)) {
      transparency += mean(v.throughput);
      return;
    }
    const Color before = emitted;
    see_suns(v, emitted);
    if (seen) seen->emission += emitted - before;
    Color world(0.0);
    if (v.ray.kind == kCameraRay && scene.camera_background() != nullptr)
      world = v.throughput * scene.camera_background()->radiance(v.ray.direction);
    else if (background != nullptr && (background->visibility & v.ray.kind) && reaches(*background, v.depth))
      world = v.throughput * background_radiance(*background, v.ray.direction) * bsdf_share(v, *background);
    emitted += world;
    if (seen) seen->environment += world;
  }

  // Cycles: a camera ray that meets a holdout cuts a hole, whether or not the film is transparent.
  // Other rays see a Holdout object as its material, the Holdout shader black. True if the path ends.
  bool ends_at_holdout(const EyeVertex& v, const Hit& hit, const Material& m, double& transparency) const {
    // A mixture's Holdout closures cut their weight out of the alpha and shade with the rest.
    if (m.kind == MaterialKind::Mixture && m.holdout > 0.0 && transparent_path(v))
      transparency += mean(v.throughput) * m.holdout;
    const bool holdout_shader = m.kind == MaterialKind::Holdout;
    if (!holdout_shader && !scene.is_holdout(hit)) return false;
    if (v.depth == 0 || (settings.transparent_background && transparent_path(v))) {
      transparency += mean(v.throughput);
      return true;
    }
    return holdout_shader;
  }

  // Adds the radiance of lights nearer than the surface; returns true if one blocks the view.
  bool see_lights(const EyeVertex& v, double t_surface, Color& emitted) const {
    Color seen(0.0);
    const double nearest = nearest_light(v, t_surface, seen);
    emitted += v.throughput * seen;
    return nearest < t_surface;
  }

  // The nearest light along v's ray before `t_surface`: its distance (t_surface if none) and the
  // radiance `seen` of it (weighed by bsdf_share).
  double nearest_light(const EyeVertex& v, double t_surface, Color& seen) const {
    double nearest = t_surface;
    const Light* found = nullptr;
    for (uint32_t i : visible_lights) {
      const Light& light = scene.lights()[i];
      if (!(light.visibility & v.ray.kind) || !reaches(light, v.depth)) continue;
      double t;
      const Color L = light_seen(light, v.ray, nearest, t);
      if (max_component(L) > 0.0) {
        nearest = t;
        seen = L;
        found = &light;
      }
    }
    if (found) seen *= bsdf_share(v, *found);
    return nearest;
  }

  // What the Light Path node sees at a hit `t` along v's ray. The eye chain scatters only at the
  // lobes it follows (microfacet ones, smooth or rough), whose rays it counts as singular.
  static LightPath path_of(const EyeVertex& v, double t) {
    LightPath p;
    p.kind = v.ray.kind;
    p.singular = v.depth > 0;
    p.depth = capped(v.depth);
    p.diffuse = v.chain.diffuse;
    p.glossy = v.chain.glossy;
    p.transmission = v.chain.transmission;
    p.length = static_cast<float>(t);
    return p;
  }

  // The world size of a pixel `length` along an eye path (through mirrors and glass as if straight).
  double pixel_size(double length) const { return footprint * (orthographic ? 1.0 : length); }

  // `sp`: the surface point at `hit` as v sees it (surface_point(hit, -v.ray.direction,
  // pixel_size(v.length), path_of(v, hit.t))).
  // Inlined into both of trace_paths' instances, as it was into the one trace before media.
  [[gnu::always_inline]] void record(const Hit& hit, const SurfacePoint& sp, const EyeVertex& v, uint32_t pixel,
                                     ChunkOutput& out, SampleFeatures* features) const {
    const Material& m = scene.material(hit.material);
    const Vec3 wo = -v.ray.direction;
    const LightPath path = path_of(v, hit.t);
    const bool front = glm::dot(wo, sp.ng) >= 0.0;
    const Vec3 ns = front ? sp.ns : -sp.ns;
    Color albedo;
    const bool glossy = !bsdf_lambertian(m, sp, wo, albedo);
    double r = settings.initial_radius;
    if (r <= 0.0) r = settings.initial_radius_pixels * pixel_size(v.length);
    r = std::fmax(r, 4.0 * ray_offset(hit.position, scene.offset_floor()));
    HitPoint hp;
    hp.position = hit.position;
    hp.normal = Vec3f(ns);
    hp.shading = static_cast<uint32_t>(out.shading.size());
    hp.r2 = r * r;
    hp.weight = Vec3f(glossy ? v.throughput : v.throughput * albedo * kInvPi);
    hp.glossy = glossy ? 1u : 0u;
    out.points.push_back(hp);
    out.shading.push_back(
        HitPointShading{sp.ng, Vec3f(sp.ns), Vec3f(wo), Vec3f(v.throughput), Vec2f(hit.uv), Vec3f(sp.smooth_normal),
                        sp.tangent != Vec3(0.0) ? hit.tangent : glm::vec4(0.0f), hit.material, hit.object,
                        hit.primitive, pixel, path});
    if (limits.active) out.chain.push_back(v.chain);
    if (options.record_components) out.route.push_back(v.route);
    if (features && !v.features_done) features->add(v.throughput, denoising_albedo(m, sp, wo), ns, v.share);
  }

  // What a medium step (below) decided for the segment of v's ray up to the surface.
  struct MediumStep {
    Color weight{1.0};          // of reaching the surface (the free-path sampler's)
    bool scattered = false;     // a hit point in the medium was recorded: the path ends
    bool behind_light = false;  // a light is nearer than the surface: the path ends there
  };

  // A free path over v's ray up to `nearest` in medium `med`: whether it scattered, where, and its
  // weight (without sigma_s when it scattered: a VolumeHitPoint's, see there). Adds what the segment
  // shows to `emitted`: the medium's emission along it and `light` (a light at `nearest`) seen
  // through it.
  struct FreePath {
    bool scattered = false;
    double distance = 0.0;
    Color weight{1.0};
    bool goes_on = false;  // scattered, and the path also goes on to the end with weight `through`
    Color through{0.0};
  };
  // A scattering's free-path weight without sigma_s (a VolumeHitPoint's).
  static Color unit_weight(const Medium& med, const Color& weight) {
    Color unit(0.0);
    for (int c = 0; c < 3; ++c) unit[c] = med.c.sigma_s[c] > 0.0 ? weight[c] / med.c.sigma_s[c] : 0.0;
    return unit;
  }
  FreePath free_path(const EyeVertex& v, const Medium& med, double nearest, const Color& light, Rng& rng,
                     Color& emitted) const {
    const bool may_scatter = !v.emission_only && med.scatters();
    if (med.varies()) {  // tracked: the light's transmittance and the emission are estimates
      if (max_component(light) > 0.0)
        emitted += v.throughput * light *
                   (med.extinction_varies() ? scene.track(med, v.ray, nearest, v.throughput, false, false, rng).weight
                                            : transmittance(med.sigma_t, nearest));
      const TrackedSegment f = scene.track(med, v.ray, nearest, v.throughput, may_scatter, true, rng);
      emitted += v.throughput * f.emitted;
      const bool scattered = f.event == FreePathEvent::Scatter;
      return {scattered, f.distance, scattered ? f.unit : f.weight};
    }
    emitted += v.throughput * (light * transmittance(med.sigma_t, nearest) + medium_emission_along(med, nearest));
    if (!may_scatter) return {false, nearest, transmittance(med.sigma_t, nearest)};
    const double u1 = rng.uniform(), u2 = rng.uniform();
    if (settings.volume_beams) return split_path(v, med, nearest, rng, u1, u2);
    const FreePathSample f = sample_free_path(med.sigma_t, med.c.sigma_s, v.throughput, nearest, u1, u2);
    if (f.event == FreePathEvent::Exit) return {false, f.distance, f.weight};
    return {true, f.distance, unit_weight(med, f.weight)};
  }

  // With Settings::volume_beams, in a homogeneous medium that scatters: the path both scatters and
  // goes on (splitting). The scattering distance is drawn within the segment (free_path.h's
  // chromatic sampling, truncated to it) with weight T(t) / pdf(t) (without sigma_s), and the path
  // goes on to the end with weight T(end), or where that is small with Russian roulette on it. In
  // thin fog most free paths cross the segment without scattering, so most camera rays drew no hit
  // point there and the fog's direct light came from a few; split, each does.
  // Half the scatterings are drawn equiangular towards a light picked by power (free_path.h), so
  // that the fog's glow about a small light is sampled where it is strong.
  FreePath split_path(const EyeVertex& v, const Medium& med, double nearest, Rng& rng, double u1, double u2) const {
    FreePath out;
    const Color through = transmittance(med.sigma_t, nearest);
    EquiangularTarget target;
    const bool toward = pick_local_light(v.ray, rng.uniform(), target);
    const FreePathSample f = sample_free_path_within(med.sigma_t, med.c.sigma_s, v.throughput, nearest, u1, u2,
                                                     toward ? &target : nullptr);
    if (f.event == FreePathEvent::Scatter) {
      out.scattered = true;
      out.distance = f.distance;
      out.weight = unit_weight(med, f.weight);
    }
    const double keep = std::fmin(1.0, max_component(through) / kSplitRoulette);
    if (keep > 0.0 && rng.uniform() < keep) {
      out.goes_on = true;
      out.through = through / keep;
    }
    if (!out.scattered) {
      out.distance = nearest;
      out.weight = out.goes_on ? out.through : Color(0.0);
    }
    return out;
  }

  // The light a split path's equiangular draws aim at (false: the scene has none with a place).
  bool pick_local_light(const Ray& ray, double u, EquiangularTarget& target) const {
    if (options.lights == nullptr || !options.lights->has_placed()) return false;
    double pdf;
    const Light& l = scene.lights()[options.lights->pick_placed(u, pdf)];
    target = EquiangularTarget::of(ray.origin, ray.direction, l.position);
    return true;
  }

  // Scenes with media: v's ray segment up to the surface at `t_surface` (kInf: none) in the medium
  // it is in. Lights nearer than the surface are seen with the medium's transmittance to them and
  // the medium's emission along the segment is added (terms of the volume rendering equation of
  // their own, whatever the free path does), then a free path is drawn; a scattering event before
  // the end records a hit point in the medium (stochastic hit points).
  MediumStep medium_step(const EyeVertex& v, const EyeMedia& vm, double t_surface, Rng& rng, uint32_t pixel,
                         ChunkOutput& out, Color& emitted) const {
    MediumStep step;
    Color light(0.0);
    const double nearest = nearest_light(v, t_surface, light);
    step.behind_light = nearest < t_surface;
    const Medium* med = scene.medium_of(vm.stack);
    if (med == nullptr) {
      emitted += v.throughput * light;
      return step;
    }
    const bool beam = settings.volume_beams && !med->varies() && !v.emission_only && med->scatters();
    if (beam) record_beam(v, *med, nearest, pixel, out);
    const FreePath f = free_path(v, *med, nearest, light, rng, emitted);
    if (!f.scattered) {
      step.weight = f.weight;
      return step;
    }
    step.scattered = !f.goes_on;
    step.weight = f.through;
    const Vec3 position = v.ray.origin + f.distance * v.ray.direction;
    double r = settings.initial_radius;
    if (r <= 0.0) r = settings.volume_radius_scale * settings.initial_radius_pixels * pixel_size(v.length + f.distance);
    r = std::fmax(r, 4.0 * ray_offset(position, scene.offset_floor()));
    VolumeHitPoint h{};
    h.position = position;
    h.weight = Vec3f(v.throughput * f.weight);
    h.direction = Vec3f(v.ray.direction);
    h.r2 = static_cast<float>(r * r);
    h.pixel = pixel;
    h.medium = scene.medium_index(med);
    h.media = vm.stack;
    h.route = v.route;
    h.chain = v.chain;
    if (beam) out.beams.back().point = static_cast<uint32_t>(out.volume.size());
    out.volume.push_back(h);
    return step;
  }

  // v's segment up to `nearest` in the homogeneous medium `med` as a beam (VolumeBeam). Its radius,
  // as a hit point's there would have, at the depth of a mean free path into the segment or its end:
  // a pixel's first beam gives its pixel's initial radius (StochasticHitPoints::start_beams).
  void record_beam(const EyeVertex& v, const Medium& med, double nearest, uint32_t pixel, ChunkOutput& out) const {
    double depth = std::fmin(nearest, 1.0 / std::fmax(max_component(med.sigma_t), 1e-30));
    if (!std::isfinite(depth)) depth = 0.0;  // no extinction and no end
    double r = settings.initial_radius;
    if (r <= 0.0) r = settings.volume_radius_scale * settings.initial_radius_pixels * pixel_size(v.length + depth);
    r = std::fmax(r, 4.0 * ray_offset(v.ray.origin, scene.offset_floor()));
    VolumeBeam b{};
    b.r2 = static_cast<float>(r * r);
    b.origin = v.ray.origin;
    b.direction = Vec3f(v.ray.direction);
    b.length = static_cast<float>(std::fmin(nearest, 3.0e38));
    b.weight = Vec3f(v.throughput);
    b.sigma_t = Vec3f(med.sigma_t);
    b.pixel = pixel;
    b.medium = scene.medium_index(&med);
    b.route = v.route;
    b.chain = v.chain;
    b.point = kNoPoint;
    out.beams.push_back(b);
  }

  // Adds what the path sees directly to `emitted` and what of it is transparent to `transparency`.
  // `features`: nullptr, or where this sample's denoising features go; `seen`: nullptr, or where
  // what it sees at no bounce goes (as well as into `emitted`); `components`: nullptr, or where
  // its light components go (emission after a bounce, the Color passes).
  // Compiled twice (trace_pixel<kMedia>): scenes without media run the loop they ran before media
  // existed (kMedia false: no media step, and the compiler inlines as it did; measured with
  // callgrind, tools in the commit message).
  template <bool kMedia>
  [[gnu::always_inline]] void trace_paths(const Ray& primary, const Color& weight, Rng& rng, uint32_t pixel, ChunkOutput& out,
                   Color& emitted, double& transparency, SampleFeatures* features, SeenLight* seen,
                   ComponentLight* components) const {
    EyeVertex stack[2 * kSplitDepth + 4];
    std::conditional_t<kMedia, EyeMedia[2 * kSplitDepth + 4], EyeMedia*> media_of = {};  // kMedia: beside stack
    int top = 0;
    stack[top++] = EyeVertex{primary, weight, 0, 0.0, true, Bounces{}, false};
    if constexpr (kMedia) media_of[0].stack = scene.camera_ray_media(primary.origin);  // a camera in fog is in it
    const double tmax0 = scene.camera().clip_end - scene.camera().clip_start;
    while (top > 0) {
      EyeVertex v = stack[--top];
      [[maybe_unused]] std::conditional_t<kMedia, EyeMedia, char> vm{};  // kMedia: the vertex's media
      if constexpr (kMedia) vm = media_of[top];
      FileEmission file{components, v, emitted, emitted};
      Hit hit;
      const bool found = scene.intersect(v.ray, hit, v.depth == 0 ? tmax0 : kInf);
      SeenLight* seen_here = v.depth == 0 ? seen : nullptr;  // Cycles' Emit and Env: no bounce
      const Color before = emitted;
      if constexpr (kMedia) {
        const MediumStep step = medium_step(v, vm, found ? hit.t : kInf, rng, pixel, out, emitted);
        if (seen_here) seen_here->emission += emitted - before;
        if (step.scattered || step.behind_light) continue;
        v.throughput *= step.weight;
        if (!(max_component(v.throughput) > 0.0)) continue;
      } else {
        const bool behind_a_light = see_lights(v, found ? hit.t : kInf, emitted);
        if (seen_here) seen_here->emission += emitted - before;
        if (behind_a_light) continue;
      }
      if (!found) {
        escape(v, emitted, transparency, seen_here);
        continue;
      }
      const Material& m = scene.material(hit.material);
      if constexpr (kMedia) {
        if (!m.surface) {  // a boundary only: the same ray goes on in the next medium
          if (++vm.crossings > kMaxMediumCrossings) continue;
          scene.cross(hit, v.ray.direction, vm.stack);
          v.ray.origin = offset_point(hit.position, hit.geometric_normal, v.ray.direction, scene.offset_floor());
          v.length += hit.t;
          media_of[top] = vm;
          stack[top++] = v;
          continue;
        }
      }
      if (ends_at_holdout(v, hit, m, transparency)) continue;
      if (m.emits()) {
        const Color emission = v.throughput * scene.emission(hit, -v.ray.direction, path_of(v, hit.t));
        emitted += emission;
        if (seen_here) seen_here->emission += emission;
      }
      if (is_black(m) || v.emission_only) continue;
      const double length = v.length + hit.t;
      const SurfacePoint sp = scene.surface_point(hit, -v.ray.direction, pixel_size(length), path_of(v, hit.t));
      if (components && v.depth == 0) {  // Cycles' Color passes: at the surfaces the camera sees
        const ClassColors albedo = bsdf_class_albedo(m, sp, -v.ray.direction);
        for (int c = 0; c < kLightClasses; ++c) components->color[c] += Vec3f(v.throughput * albedo.c[c]);
      }
      const double followed = followed_share(m, sp, -v.ray.direction);
      // A mixture of followed and stored lobes: one or the other, divided by its probability.
      if (!(followed >= 1.0 || (followed > 0.0 && rng.uniform() < followed))) {
        EyeVertex stored = v;
        stored.length = length;
        stored.throughput /= 1.0 - followed;
        record(hit, sp, stored, pixel, out, features);
        if constexpr (kMedia) out.media.push_back(vm.stack);  // its shadow rays start in these media
        continue;
      }
      // With Cycles' limits, one ray more than the total: it may still see emission.
      if (!options.follow_specular || v.depth + 1 >= settings.path_bounces() + (limits.by_kind ? 1 : 0)) continue;
      const bool rough = settings.followed_light != FollowedLight::Draws && m.kind == MaterialKind::Mixture &&
                         closure_has_rough_followed(m.lobes, sp);
      if (rough && !(delta_lights.empty() && pdf_lights.empty())) {
        const MediumStack* media = nullptr;
        if constexpr (kMedia) media = &vm.stack;
        sample_lights(v, hit, m, sp, followed, media, rng, emitted, file);
      }
      if (features && !v.features_done && m.kind == MaterialKind::Mixture) {  // Cycles' features stop here
        const Vec3 wo = -v.ray.direction;
        const Color albedo = closure_followed_albedo(m.lobes, sp, wo);
        if (max_component(albedo) > 0.0)
          features->add(v.throughput / followed, albedo, glm::dot(wo, sp.ng) >= 0.0 ? sp.ns : -sp.ns, v.share);
      }
      const int first_branch = top;
      follow_specular(v, length, hit, m, sp, followed, rough && !pdf_lights.empty(), rng, stack, top);
      if constexpr (kMedia) {  // each branch keeps v's media, and changes them where it goes through the surface
        for (int b = first_branch; b < top; ++b) {
          media_of[b] = vm;
          const Vec3 wi = stack[b].ray.direction;
          if (glm::dot(wi, hit.geometric_normal) * glm::dot(v.ray.direction, hit.geometric_normal) > 0.0)
            scene.cross(hit, v.ray.direction, media_of[b].stack);
        }
      }
    }
  }

  // A path that follows rough lobes (closure_eval_followed_rough) at `hit`, with probability
  // `followed`, stores no hit point for them: the lights they reflect are sampled here, a shadow
  // ray each, added to `emitted` and filed as the reflection or refraction that carries them.
  // Lights of no size, which no drawn direction meets, in full; lights with a density
  // (light_has_pdf) by the balance heuristic against the lobes' own draw, which weighs what it
  // meets alike (bsdf_share). Emissive triangles and a plain world are left to the lobes' draw.
  // `media`: the stack v is in (scenes with media), for the shadow rays' transmittance.
  void sample_lights(const EyeVertex& v, const Hit& hit, const Material& m, const SurfacePoint& sp, double followed,
                     const MediumStack* media, Rng& rng, Color& emitted, FileEmission& file) const {
    for (uint32_t i : delta_lights) {
      DirectSample ds;
      if (sample_direct(scene.lights()[i], hit.position, sp.ns, 0.5, 0.5, ds))
        add_light_sample(v, hit, m, sp, scene.lights()[i], ds, 1.0 / followed, media, rng, emitted, file);
    }
    for (uint32_t i : pdf_lights) {
      const Light& light = scene.lights()[i];
      const double u1 = rng.uniform(), u2 = rng.uniform();
      DirectSample ds;
      if (!sample_light_with_pdf(light, hit.position, u1, u2, ds)) continue;
      const double p_light = light_pdf(light, hit.position, ds.wi);
      if (!(p_light > 0.0)) continue;
      const double p_bsdf = settings.followed_light == FollowedLight::Lights
                                ? 0.0
                                : closure_followed_pdf(m.lobes, sp, -v.ray.direction, ds.wi);
      add_light_sample(v, hit, m, sp, light, ds, p_light / ((p_light + p_bsdf) * followed), media, rng, emitted,
                       file);
    }
  }

  // One light sample `ds` of sample_lights, times `scale`.
  void add_light_sample(const EyeVertex& v, const Hit& hit, const Material& m, const SurfacePoint& sp,
                        const Light& light, const DirectSample& ds, double scale, const MediumStack* media, Rng& rng,
                        Color& emitted, FileEmission& file) const {
    const Vec3 wo = -v.ray.direction;
    const bool reflected = glm::dot(ds.wi, hit.geometric_normal) * glm::dot(wo, hit.geometric_normal) > 0.0;
    const uint8_t kind = reflected ? kGlossyRay : kTransmissionRay;
    if (!reaches(light, v.depth) || !(light.visibility & kind)) return;  // Cycles leaves it out of those closures
    const Color f = closure_eval_followed_rough(m.lobes, sp, wo, ds.wi);
    Color c = v.throughput * f * ds.value * (std::fabs(glm::dot(sp.ns, ds.wi)) * scale);
    if (!(max_component(c) > 0.0)) return;
    c *= shadow_weight(hit, v.ray.direction, ds, light.cast_shadow, media, rng);
    if (!(max_component(c) > 0.0)) return;
    emitted += c;
    file.file_apart(c, emission_component(route_after(v.route, kind), v.depth + 1));
  }

  // What reaches `hit` of a light sample `ds` past the shadows (1 or 0; in media, their transmittance).
  Color shadow_weight(const Hit& hit, const Vec3& incoming, const DirectSample& ds, bool casts_shadow,
                      const MediumStack* media, Rng& rng) const {
    if (!casts_shadow) return Color(1.0);
    const Ray ray{offset_point(hit.position, hit.geometric_normal, ds.wi, scene.offset_floor()), ds.wi, kShadowRay};
    const double dist = shadow_distance(hit.position, ds, scene.offset_floor());
    if (!(dist > 0.0)) return Color(0.0);
    if (media == nullptr) return scene.occluded(ray, dist) ? Color(0.0) : Color(1.0);
    MediumStack stack = *media;  // through the surface: the media beyond it
    if (glm::dot(ds.wi, hit.geometric_normal) * glm::dot(incoming, hit.geometric_normal) > 0.0)
      scene.cross(hit, incoming, stack);
    return scene.shadow_transmittance(ray, dist, stack, rng);
  }

  // The share of m's scattering at sp that eye paths follow: its mirror and smooth glass lobes'.
  static double followed_share(const Material& m, const SurfacePoint& sp, const Vec3& wo) {
    if (is_specular(m)) return 1.0;
    if (m.kind == MaterialKind::Mixture && closure_has_followed(m.lobes))
      return closure_followed_share(m.lobes, sp, wo);
    return 0.0;
  }

  // Pushes the rays v follows from a mirror or glass at `hit` (their share `followed` of its
  // scattering) onto `stack`: both branches of a split up to kSplitDepth, one chosen past it.
  // `weigh`: light was sampled at the vertex too (sample_lights), so a direction drawn from a rough
  // lobe carries its density (EyeVertex::mis_pdf).
  [[gnu::always_inline]] void follow_specular(const EyeVertex& v, double length, const Hit& hit, const Material& m,
                                              const SurfacePoint& sp, double followed, bool weigh, Rng& rng,
                                              EyeVertex* stack, int& top) const {
    BsdfSample branches[2];
    double u[4] = {0.5, 0.5, 0.5, 0.5};  // only a mixture draws: other scenes keep their random streams
    if (m.kind == MaterialKind::Mixture)
      for (double& x : u) x = rng.uniform();
    int count = specular_branches(m, sp, -v.ray.direction, u[0], u[1], u[2], u[3], branches);
    for (int b = 0; b < count; ++b) branches[b].weight /= followed;
    if (count == 2 && v.depth >= kSplitDepth) {  // past the split depth: follow one branch
      const double w0 = luminance(branches[0].weight), w1 = luminance(branches[1].weight);
      const double p0 = w0 + w1 > 0.0 ? w0 / (w0 + w1) : 0.5;
      const int pick = rng.uniform() < p0 ? 0 : 1;
      branches[0] = branches[pick];
      branches[0].weight /= pick == 0 ? p0 : 1.0 - p0;
      count = 1;
    }
    const double split = count == 2 ? luminance(branches[0].weight) + luminance(branches[1].weight) : 0.0;
    for (int b = 0; b < count; ++b) {
      const Color thr = v.throughput * branches[b].weight;
      const double share = v.share * (split > 0.0 ? luminance(branches[b].weight) / split : 1.0);
      if (!(max_component(thr) > 0.0)) continue;
      const Vec3 wi = branches[b].wi;
      const Vec3 origin = offset_point(hit.position, hit.geometric_normal, wi, scene.offset_floor());
      const uint8_t kind = branches[b].ray_kind ? branches[b].ray_kind : v.ray.kind;  // 0: transparency
      const bool through = branches[b].ray_kind == 0 || branches[b].ray_kind == kTransmissionRay;
      const bool glass_only =
          v.glass_only && through && (m.kind == MaterialKind::Glass || m.kind == MaterialKind::Mixture);
      const Bounces chain = plus(v.chain, kind);
      const bool emission_only = limits.by_kind && !within(chain, limits.max);
      if (branches[b].ray_kind == 0) {  // through a transparent lobe: no bounce, as Cycles counts it
        stack[top++] = EyeVertex{Ray{origin, wi, v.ray.kind}, thr, v.depth, length, v.glass_only, v.chain,
                                 v.emission_only, share, v.route, 0.0, v.features_done};
        continue;
      }
      const double mis_pdf =
          weigh && !branches[b].specular ? closure_followed_pdf(m.lobes, sp, -v.ray.direction, wi) : 0.0;
      const int lobe = branches[b].lobe;
      const bool features_done = v.features_done || (lobe >= 0 && m.lobes[lobe].rough_for_denoising(sp));
      stack[top++] = EyeVertex{Ray{origin, wi, kind}, thr,   v.depth + 1, length, glass_only,
                               chain, emission_only, share, route_after(v.route, kind), mis_pdf, features_done};
    }
  }
};

// A sample's features into its pixel's: albedo summed (the throughput has 1/spp), the normal a
// mean over the samples, each the normals of its hit points weighted by the chance a single path
// goes there (a branch to the sky adds nothing, as in Cycles).
void add_features(const SampleFeatures& f, int spp, Vec3f& albedo, Vec3f& normal) {
  albedo += Vec3f(f.albedo);
  normal += Vec3f(f.normal / double(spp));
}

// The tracer of one pass, with the lights its rays can see: those with a surface, suns with a disc
// in the sky, and the world.
EyeTracer make_tracer(const Scene& scene, const Settings& settings, const EyePassOptions& options) {
  const Camera& cam = scene.camera();
  EyeTracer tracer{scene, settings, options, {}, {}, {}, {}, nullptr, cam.pixel_footprint(),
                   cam.projection == Projection::Orthographic, BounceLimits::of(settings, scene), scene.has_media()};
  for (uint32_t i = 0; i < scene.lights().size(); ++i) {
    const LightKind k = scene.lights()[i].kind;
    const bool spot_sphere = k == LightKind::Spot && scene.lights()[i].radius > 0.0;
    if (k == LightKind::Sphere || spot_sphere || k == LightKind::Rectangle || k == LightKind::Disk)
      tracer.visible_lights.push_back(i);
    if (k == LightKind::Sun && scene.lights()[i].cos_sun < 1.0) tracer.visible_suns.push_back(i);
    if (k == LightKind::Background) tracer.background = &scene.lights()[i];
    if (light_is_delta(scene.lights()[i])) tracer.delta_lights.push_back(i);
    if (light_has_pdf(scene.lights()[i])) tracer.pdf_lights.push_back(i);
  }
  return tracer;
}

// The band of rows a pass traces, its pixels and its chunks of kRowsPerChunk rows.
struct Band {
  int row_begin, row_end;
  size_t first_pixel, pixels, chunks;
};

Band band_of(const Camera& cam, const EyePassOptions& options) {
  Band b;
  b.row_begin = std::clamp(options.row_begin, 0, cam.height);
  b.row_end = options.row_end < 0 ? cam.height : std::clamp(options.row_end, b.row_begin, cam.height);
  b.first_pixel = static_cast<size_t>(b.row_begin) * cam.width;
  b.pixels = static_cast<size_t>(b.row_end - b.row_begin) * cam.width;
  b.chunks = (b.row_end - b.row_begin + kRowsPerChunk - 1) / kRowsPerChunk;
  return b;
}

// The per-pixel outputs of a band, sized and cleared (those the options do not ask for emptied).
void reset_pixel_outputs(const EyePassOptions& options, size_t pixels, HitPoints& out, std::vector<uint32_t>& counts) {
  const int spp = options.samples_per_pixel;
  out.emitted.assign(pixels, Color(0.0));
  out.transparency.assign(pixels, 0.0);
  counts.assign(pixels, 0);
  if (options.record_depth) out.depth.assign(pixels, std::numeric_limits<float>::infinity());
  else out.depth.clear();
  out.sample_light.assign(options.record_samples ? pixels * spp : 0, 0.0f);
  out.seen.assign(options.record_seen ? pixels : 0, SeenLight{});
  out.albedo.assign(options.record_features ? pixels : 0, Vec3f(0.0f));
  out.pixel_components.assign(options.record_components ? pixels : 0, ComponentLight{});
  out.feature_normal.assign(options.record_features ? pixels : 0, Vec3f(0.0f));
}

// A chunk's hit-point lists emptied, with room for about one hit point per eye sample (reserving
// saves the regrowth copies and their page faults).
void clear_chunk(ChunkOutput& o, size_t samples, bool chains) {
  o.points.clear();
  o.shading.clear();
  o.chain.clear();
  o.sample.clear();
  o.route.clear();
  o.media.clear();
  o.volume.clear();
  o.beams.clear();
  o.points.reserve(samples);
  o.shading.reserve(samples);
  if (chains) o.chain.reserve(samples);
}

// One pixel's eye samples: hit points into chunk `o`, its per-pixel outputs at `local` of `out`.
// Returns the number of hit points it made.
template <bool kMedia>
uint32_t trace_pixel(const EyeTracer& tracer, const CameraRays& rays, int x, int y, size_t local, ChunkOutput& o,
                     HitPoints& out) {
  const EyePassOptions& options = tracer.options;
  const Camera& cam = tracer.scene.camera();
  const int spp = options.samples_per_pixel;
  const uint32_t pixel = static_cast<uint32_t>(y) * cam.width + x;  // row 0 = bottom
  const size_t before = o.points.size();
  double depth_sum = 0.0;
  int depth_count = 0;
  const int samples = options.pixel_samples ? std::clamp<int>(options.pixel_samples[pixel], 1, spp) : spp;
  const int lattice = static_cast<int>(std::floor(std::sqrt(static_cast<double>(samples))));
  for (int s = 0; s < samples; ++s) {
    Rng rng(tracer.settings.seed, kEyeStream + options.generation, static_cast<uint64_t>(pixel) * spp + s);
    // Stratified on a lattice x lattice grid for the first lattice^2 samples, then uniform.
    double jx = rng.uniform(), jy = rng.uniform();
    if (s < lattice * lattice) {
      jx = (s % lattice + jx) / lattice;
      jy = (s / lattice + jy) / lattice;
    }
    const double lu = rng.uniform(), lv = rng.uniform();
    Ray ray = options.lens ? rays.through_lens(x + jx, y + jy, lu, lv) : rays.through(x + jx, y + jy);
    ray.kind = kCameraRay;
    if (options.record_depth) {
      Hit first;
      if (tracer.scene.intersect(ray, first)) {
        depth_sum += cam.depth_of(first.position);
        ++depth_count;
      }
    }
    SampleFeatures features;
    const double light_before = luminance(out.emitted[local]);
    tracer.trace_paths<kMedia>(ray, Color(1.0 / samples), rng, pixel, o, out.emitted[local], out.transparency[local],
                 options.record_features ? &features : nullptr, options.record_seen ? &out.seen[local] : nullptr,
                 options.record_components ? &out.pixel_components[local] : nullptr);
    if (options.record_samples) {
      o.sample.resize(o.points.size(), static_cast<uint16_t>(s));
      out.sample_light[local * spp + s] = static_cast<float>(luminance(out.emitted[local]) - light_before);
    }
    if (options.record_features) add_features(features, samples, out.albedo[local], out.feature_normal[local]);
  }
  if (depth_count > 0) out.depth[local] = static_cast<float>(depth_sum / depth_count);
  return static_cast<uint32_t>(o.points.size() - before);
}

// The chunks' hit points concatenated in order into `out`, each chunk copied by whichever thread
// takes it; with release_chunks, each chunk freed once copied.
void join_chunks(std::vector<ChunkOutput>& outputs, size_t chunks, const EyePassOptions& options, bool chains,
                 HitPoints& out) {
  std::vector<size_t> first(chunks + 1, 0);
  for (size_t c = 0; c < chunks; ++c) first[c + 1] = first[c] + outputs[c].points.size();
  const size_t total = first[chunks];
  out.points.resize(total);
  out.shading.resize(total);
  out.stats.resize(total);
  out.chain.resize(chains ? total : 0);
  out.route.resize(options.record_components ? total : 0);
  bool media = false;
  size_t volume = 0, beams = 0;
  for (size_t c = 0; c < chunks; ++c)
    media |= !outputs[c].media.empty(), volume += outputs[c].volume.size(), beams += outputs[c].beams.size();
  out.media.resize(media ? total : 0);
  out.volume.clear();
  out.beams.clear();
  if (media || volume || beams) {  // scenes with media: their stacks beside the hit points, hit points and beams in media
    out.volume.reserve(volume);
    out.beams.reserve(beams);
    for (size_t c = 0; c < chunks; ++c) {
      std::copy(outputs[c].media.begin(), outputs[c].media.end(), out.media.begin() + first[c]);
      const auto points_before = static_cast<uint32_t>(out.volume.size());
      out.volume.insert(out.volume.end(), outputs[c].volume.begin(), outputs[c].volume.end());
      for (VolumeBeam b : outputs[c].beams) {
        if (b.point != kNoPoint) b.point += points_before;
        out.beams.push_back(b);
      }
    }
  }
  out.components.resize(options.record_components ? total : 0);
  auto join = [&](size_t c) {
    ChunkOutput& o = outputs[c];
    for (size_t k = 0; k < o.points.size(); ++k) {
      HitPoint hp = o.points[k];
      hp.shading += static_cast<uint32_t>(first[c]);
      out.points[first[c] + k] = hp;
      out.shading[first[c] + k] = o.shading[k];
      out.stats[first[c] + k] = HitPointStats{};
      if (options.record_samples) out.stats[first[c] + k].sample = o.sample[k];
      if (chains) out.chain[first[c] + k] = o.chain[k];
      if (options.record_components) {
        out.route[first[c] + k] = o.route[k];
        out.components[first[c] + k] = HitPointComponents{};
      }
    }
    if (options.release_chunks) o = ChunkOutput();
  };
  // Released chunks go back to the system a batch at a time (malloc keeps small blocks otherwise),
  // while `out`'s pages are first written as the chunks are joined.
  const size_t batch = options.release_chunks ? 64 : chunks;
  for (size_t begin = 0; begin < chunks; begin += batch) {
    const size_t n = std::min(batch, chunks - begin);
    parallel_each(options.threads, n, [&](size_t c) { join(begin + c); });
    if (options.release_chunks) return_freed_memory();
  }
}

}  // namespace

size_t EyePassScratch::memory_bytes() const {
  size_t bytes = counts.capacity() * sizeof(uint32_t);
  for (const Chunk& c : chunks)
    bytes += c.points.capacity() * sizeof(HitPoint) + c.shading.capacity() * sizeof(HitPointShading) +
             c.chain.capacity() * sizeof(Bounces) + c.route.capacity() + c.media.capacity() * sizeof(MediumStack) +
             c.volume.capacity() * sizeof(VolumeHitPoint) + c.beams.capacity() * sizeof(VolumeBeam);
  return bytes;
}

bool eye_pass(const Scene& scene, const Settings& settings, const EyePassOptions& options, HitPoints& out,
              EyePassScratch& scratch, std::atomic<bool>& cancel, const std::function<bool()>& poll) {
  const EyeTracer tracer = make_tracer(scene, settings, options);
  const Camera& cam = scene.camera();
  const CameraRays rays(cam);
  const Band band = band_of(cam, options);
  if (scratch.chunks.size() < band.chunks) scratch.chunks.resize(band.chunks);
  std::vector<ChunkOutput>& outputs = scratch.chunks;
  std::vector<uint32_t>& counts = scratch.counts;
  reset_pixel_outputs(options, band.pixels, out, counts);
  const size_t chunk_samples = size_t(kRowsPerChunk) * cam.width * options.samples_per_pixel;
  auto work = [&](int, size_t chunk) {
    ChunkOutput& o = outputs[chunk];
    clear_chunk(o, chunk_samples, tracer.limits.active);
    const int y_begin = band.row_begin + static_cast<int>(chunk) * kRowsPerChunk;
    for (int y = y_begin; y < std::min(band.row_end, y_begin + kRowsPerChunk); ++y)
      for (int x = 0; x < cam.width; ++x) {
        const size_t local = static_cast<size_t>(y) * cam.width + x - band.first_pixel;  // in this band
        counts[local] = tracer.media ? trace_pixel<true>(tracer, rays, x, y, local, o, out)
                                     : trace_pixel<false>(tracer, rays, x, y, local, o, out);
      }
  };
  if (!parallel_chunks(options.threads, band.chunks, work, cancel, poll, settings.progress_interval)) return false;
  join_chunks(outputs, band.chunks, options, tracer.limits.active, out);
  out.pixel_begin.assign(counts.size() + 1, 0);
  for (size_t p = 0; p < counts.size(); ++p) out.pixel_begin[p + 1] = out.pixel_begin[p] + counts[p];
  return true;
}

}  // namespace ppm
