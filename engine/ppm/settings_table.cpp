// The settings table: each setting's name, type, documentation, and how it is read and written.
#include "ppm/settings_table.h"

#include "base/utf8.h"
#include "scene/scene.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace ppm {
namespace {

template <class T>
constexpr SettingType type_of() {
  if constexpr (std::is_same_v<T, bool>) return SettingType::Bool;
  if constexpr (std::is_same_v<T, int>) return SettingType::Int;
  if constexpr (std::is_same_v<T, uint32_t>) return SettingType::UInt32;
  if constexpr (std::is_same_v<T, uint64_t>) return SettingType::UInt64;
  if constexpr (std::is_same_v<T, double>) return SettingType::Double;
}

template <class T>
SettingInfo number(const char* name, T Settings::*field, const char* doc) {
  return {name, type_of<T>(), doc, [field](const Settings& s) { return SettingValue(std::in_place_type<T>, s.*field); },
          [field, name = std::string(name)](Settings& s, const SettingValue& v) {
            if (!std::holds_alternative<T>(v)) wrong_setting_type(name);
            s.*field = std::get<T>(v);
          }};
}

template <class E>
SettingInfo choice(const char* name, E Settings::*field, std::vector<std::pair<const char*, E>> names,
                   const char* doc) {
  return {name, SettingType::Choice, doc,
          [field, names](const Settings& s) {
            for (const auto& [n, e] : names)
              if (s.*field == e) return SettingValue(std::string(n));
            return SettingValue(std::string("?"));
          },
          [field, names, key = std::string(name)](Settings& s, const SettingValue& v) {
            if (!std::holds_alternative<std::string>(v)) wrong_setting_type(key);
            const std::string& value = std::get<std::string>(v);
            std::string options;
            for (const auto& [n, e] : names) {
              if (value == n) {
                s.*field = e;
                return;
              }
              options += std::string(options.empty() ? "'" : ", '") + n + "'";
            }
            throw std::invalid_argument("settings: " + key + " must be one of " + options + ", not '" +
                                        printable(value) + "'");
          }};
}

std::vector<SettingInfo> make_table() {
  std::vector<SettingInfo> table = {
      number("photons_per_pass", &Settings::photons_per_pass, "photons traced per pass"),
      number("alpha", &Settings::alpha, "radius reduction alpha in (0, 1)"),
      number("threshold", &Settings::threshold, "P of the cross-generation rule (1 = classic PPM)"),
      number("max_bounces", &Settings::max_bounces, "longest photon path / eye specular chain"),
      number("light_path_limits", &Settings::light_path_limits,
             "honour total/diffuse/glossy/transmission/volume_bounces as Cycles' Light Paths"),
      number("total_bounces", &Settings::total_bounces, "light_path_limits: scatterings of a full path"),
      number("diffuse_bounces", &Settings::diffuse_bounces, "light_path_limits: diffuse scatterings"),
      number("glossy_bounces", &Settings::glossy_bounces, "light_path_limits: glossy scatterings"),
      number("transmission_bounces", &Settings::transmission_bounces, "light_path_limits: transmission scatterings"),
      number("volume_bounces", &Settings::volume_bounces, "light_path_limits: scatterings in media"),
      number("samples_per_pixel", &Settings::samples_per_pixel, "jittered eye samples per pixel"),
      number("seed", &Settings::seed, "random seed"),
      number("threads", &Settings::threads, "worker threads, 0 = all cores"),
      number("initial_radius", &Settings::initial_radius, "initial gather radius in metres, 0 = automatic"),
      number("initial_radius_pixels", &Settings::initial_radius_pixels, "automatic initial radius in pixel footprints"),
      number("volume_radius_scale", &Settings::volume_radius_scale,
             "hit points in media: the automatic initial radius times this, (0, 1e6]"),
      number("volume_beams", &Settings::volume_beams,
             "in homogeneous media that scatter: camera paths split (each samples a scattering within its "
             "segment and goes on), and photons that reached the medium along specular bounces are kept as "
             "photon beams that camera segments gather (Beam x Beam 1D); false: volume photons are points, "
             "gathered where a free path scatters"),
      number("volume_boundary", &Settings::volume_boundary,
             "hit points in media: divide their photons by the share of the gather ball on their side of "
             "the nearest surface (found by rays along the axes), where no photon lies beyond, and in a "
             "medium that varies by the ball's mean density over the centre's"),
      number("density_radius", &Settings::density_radius,
             "widen the automatic initial radius where one pass's photons are sparser than pixels"),
      number("progress_interval", &Settings::progress_interval, "seconds between progress callbacks"),
      choice("direct_light", &Settings::direct_light, {{"sampled", DirectLight::Sampled}, {"photons", DirectLight::Photons}},
             "'sampled': light sampling + photons for indirect; 'photons': photons carry all"),
      choice("followed_light", &Settings::followed_light,
             {{"mis", FollowedLight::Mis}, {"lights", FollowedLight::Lights}, {"draws", FollowedLight::Draws}},
             "light reflected by glossy and refracting lobes, which eye paths follow: 'mis' (light sampling and "
             "the lobe's draw, by the balance heuristic), 'lights' or 'draws' alone (to compare)"),
      choice("gather", &Settings::gather,
             {{"hit_points", GatherOrganisation::HitPoints}, {"photons", GatherOrganisation::Photons}},
             "which set the grid organises: 'hit_points' (photons query) or 'photons'"),
      choice("hit_points", &Settings::hit_points, {{"fixed", HitPointMode::Fixed}, {"stochastic", HitPointMode::Stochastic}},
             "'fixed' (PPM: one eye pass) or 'stochastic' (SPPM: new eye samples each pass)"),
      choice("hit_point_storage", &Settings::hit_point_storage,
             {{"auto", HitPointStorage::Auto}, {"kept", HitPointStorage::Kept}, {"streamed", HitPointStorage::Streamed}},
             "fixed hit points: 'kept' for the render, 'streamed' (made again each pass, 48 bytes each kept) or "
             "'auto' (kept where memory allows)"),
      choice("dof_mode", &Settings::dof_mode, {{"off", DofMode::Off}, {"post", DofMode::Post}, {"lens", DofMode::Lens}},
             "depth of field: 'off', 'post' (blur by depth) or 'lens' (thin-lens sampling)"),
      choice("dof_post_preset", &Settings::dof_post_preset,
             {{"thin_lens", DofPostPreset::ThinLens}, {"report_thirds", DofPostPreset::ReportThirds}},
             "POST blur: 'thin_lens' circle of confusion or the report's 'report_thirds'"),
      number("dof_max_radius", &Settings::dof_max_radius, "POST: largest blur radius in pixels"),
      number("scene_analysis", &Settings::scene_analysis, "skip work the scene cannot use (False: benchmarks)"),
      number("transparent_background", &Settings::transparent_background,
             "camera rays that escape leave alpha 0 (Film > Transparent)"),
      number("transparent_glass", &Settings::transparent_glass,
             "with transparent_background: also rays escaping through smooth glass"),
      number("target_error", &Settings::target_error,
             "stop once the image's estimated relative error is at most this (0: off)"),
      number("error_confidence", &Settings::error_confidence,
             "confidence of the error estimate's noise bound, in (0, 1)"),
      number("error_min_passes", &Settings::error_min_passes, "passes before target_error can stop a run"),
      number("light_passes", &Settings::light_passes,
             "keep the emission and the world camera rays see at no bounce apart (light_passes())"),
      number("component_passes", &Settings::component_passes,
             "keep Diffuse, Glossy and Transmission Direct, Indirect and Color and the caustic part apart "
             "(component_passes())"),
      number("photon_guiding", &Settings::photon_guiding,
             "guide point, sphere, spot and area lights' photons towards the pixels the error estimate finds "
             "noisiest"),
      number("adaptive_samples", &Settings::adaptive_samples,
             "stochastic hit points: up to this many eye samples a pixel each pass where the error estimate finds "
             "the pixel noisiest (1: one everywhere)"),
      choice("radius_schedule", &Settings::radius_schedule,
             {{"progressive", RadiusSchedule::Progressive}, {"global", RadiusSchedule::Global}},
             "stochastic hit points: 'progressive' (per pixel, with the threshold P) or 'global' (from the pass's "
             "index, Knaus & Zwicker 2011: passes render apart and merge, share())"),
      number("first_pass", &Settings::first_pass,
             "with radius_schedule 'global': the index of the first pass this renderer renders"),
      choice("grid", &Settings::grid, {{"quantile", GridKind::Quantile}, {"hash", GridKind::Hash}},
             "spatial index: 'quantile' grid or 'hash'ed uniform grid"),
  };
  std::sort(table.begin(), table.end(), [](const SettingInfo& a, const SettingInfo& b) { return a.name < b.name; });
  return table;
}

}  // namespace

const std::vector<SettingInfo>& settings_table() {
  static const std::vector<SettingInfo> table = make_table();
  return table;
}

const SettingInfo* find_setting(const std::string& name) {
  const auto& table = settings_table();
  const auto it = std::lower_bound(table.begin(), table.end(), name,
                                   [](const SettingInfo& s, const std::string& n) { return s.name < n; });
  return it != table.end() && it->name == name ? &*it : nullptr;
}

const SettingInfo& setting_named(const std::string& name) {
  if (const SettingInfo* found = find_setting(name)) return *found;
  std::string known;
  for (const SettingInfo& s : settings_table()) known += (known.empty() ? "" : ", ") + s.name;
  throw std::invalid_argument("settings: unknown setting '" + printable(name) + "' (known: " + known + ")");
}

void wrong_setting_type(const std::string& name) {
  throw std::invalid_argument("settings: " + name + " has the wrong type");
}

void check_settings(const Settings& s) {
  s.validate();
  // Radii whose square stays finite (r^2 would overflow to inf above ~1e154 m).
  if (s.initial_radius > kMaxCoordinate) throw std::invalid_argument("settings: initial_radius must be at most 1e30 m");
  if (s.initial_radius_pixels > 1e6) throw std::invalid_argument("settings: initial_radius_pixels must be at most 1e6");
  if (s.volume_radius_scale > 1e6) throw std::invalid_argument("settings: volume_radius_scale must be at most 1e6");
}

}  // namespace ppm
