// Which light to sample: photons pick a light in proportion to its flux (one
// discrete distribution over every emitter, emitting media's regions too); direct
// light samples each analytic light once and one emissive triangle chosen by flux
// (emitting media are not sampled: their photons carry their direct light); camera paths in fog aim
// at a light with a place (point, sphere, spot, rectangle, disk) chosen by power. Zero-power
// lights are left out of both (unless `drop_zero_power` is false, which the
// renderer's scene_analysis=False uses to measure what leaving them out saves).
#pragma once

#include "scene/light.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace ppm {

class LightSampler {
 public:
  explicit LightSampler(const std::vector<Light>& lights, bool drop_zero_power = true) : lights_(&lights) {
    double total = 0.0, tri_total = 0.0;
    for (uint32_t i = 0; i < lights.size(); ++i) {
      const double w = luminance(lights[i].flux);
      if (!(w > 0.0)) {
        ++dropped_;
        if (drop_zero_power) continue;
      }
      emitters_.push_back(i);
      total += w;
      emit_cdf_.push_back(total);
      if (lights[i].kind == LightKind::Triangle) {
        triangles_.push_back(i);
        tri_total += w;
        triangle_cdf_.push_back(tri_total);
      } else if (lights[i].kind == LightKind::Medium) {
        media_emit_ = media_emit_ || w > 0.0;
      } else {
        analytic_.push_back(i);
      }
      // By power, not flux: a narrow spot's flux is a sliver of its power, and the fog's glow about it
      // is not (by flux, fog_shafts' spot lost to its fill light: 1.2 times the noise at 10 s).
      const double power = luminance(lights[i].power);
      if (has_place(lights[i].kind) && power > 0.0 && power < kInf) {
        placed_total_ += power;
        placed_.push_back(i);
        placed_cdf_.push_back(placed_total_);
      }
    }
    total_ = total;
    triangle_total_ = tri_total;
  }

  // No light with power (zero-power lights kept for measuring do not count).
  bool empty() const { return !(total_ > 0.0); }
  size_t dropped() const { return dropped_; }
  const std::vector<uint32_t>& analytic() const { return analytic_; }
  bool has_triangles() const { return triangle_total_ > 0.0; }
  // Whether an emitting medium's photons are among them (their first hits are direct light).
  bool has_emitting_media() const { return media_emit_; }

  // The lights' total flux (W), picked by: a photon carries its share of it
  // (flux / (pick pdf * flux_unit), about 1 whatever the scene's scale), and
  // the gather multiplies by it (photon_radiance).
  double flux_unit() const { return total_; }

  // A light for a photon, with its selection probability. Only for a non-empty sampler.
  uint32_t pick_emitter(double u, double& pdf) const { return pick(emitters_, emit_cdf_, total_, u, pdf); }
  uint32_t pick_triangle(double u, double& pdf) const {
    return pick(triangles_, triangle_cdf_, triangle_total_, u, pdf);
  }
  bool has_placed() const { return placed_total_ > 0.0; }
  uint32_t pick_placed(double u, double& pdf) const { return pick(placed_, placed_cdf_, placed_total_, u, pdf); }

 private:
  static bool has_place(LightKind k) {
    return k == LightKind::Point || k == LightKind::Sphere || k == LightKind::Spot || k == LightKind::Rectangle ||
           k == LightKind::Disk;
  }
  uint32_t pick(const std::vector<uint32_t>& ids, const std::vector<double>& cdf, double total, double u,
                double& pdf) const {
    if (!(total > 0.0)) throw std::logic_error("LightSampler: no light with power to pick from");
    const double target = u * total;
    size_t i = std::upper_bound(cdf.begin(), cdf.end(), target) - cdf.begin();
    i = std::min(i, cdf.size() - 1);
    while (i > 0 && !(cdf[i] > cdf[i - 1])) --i;  // u * total rounded up to total: the last light with power
    const double w = cdf[i] - (i > 0 ? cdf[i - 1] : 0.0);
    pdf = w / total;
    return ids[i];
  }

  const std::vector<Light>* lights_;
  std::vector<uint32_t> emitters_, analytic_, triangles_, placed_;
  std::vector<double> emit_cdf_, triangle_cdf_, placed_cdf_;
  double total_ = 0.0, triangle_total_ = 0.0, placed_total_ = 0.0;
  size_t dropped_ = 0;
  bool media_emit_ = false;
};

}  // namespace ppm
