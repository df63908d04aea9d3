// The estimator for a render's settings (see estimator.h).
#include "ppm/estimator.h"

#include "ppm/fixed_hit_points.h"
#include "base/memory_budget.h"
#include "ppm/stochastic_hit_points.h"
#include "ppm/streamed_hit_points.h"

#include <cstdio>
#include <stdexcept>

namespace ppm {

std::unique_ptr<Estimator> make_estimator(RenderContext& context) {
  // Media render with stochastic hit points and the photons indexed (for now), with either radius
  // schedule.
  if (context.scene->has_media()) {
    const Settings& s = context.settings;
    if (s.hit_points != HitPointMode::Stochastic)
      throw std::invalid_argument("a scene with media renders with hit_points='stochastic' only (for now)");
    if (s.gather != GatherOrganisation::Photons)
      throw std::invalid_argument("a scene with media renders with gather='photons' only (for now)");
  }
  if (context.settings.hit_points == HitPointMode::Stochastic) return std::make_unique<StochasticHitPoints>(context);
  const HitPointStorage storage = context.settings.hit_point_storage;
  if (storage == HitPointStorage::Streamed) return std::make_unique<StreamedHitPoints>(context);
  if (storage == HitPointStorage::Auto) {
    // Kept while they take at most half the memory available: the rest is the user's.
    const double kept = kept_hit_point_bytes(context.scene->camera(), context.settings.samples_per_pixel,
                                             context.settings.component_passes);
    const double available = static_cast<double>(available_memory_bytes());
    if (available > 0.0 && kept > 0.5 * available) {
      char why[200];
      std::snprintf(why, sizeof why,
                    "kept fixed hit points: would need about %.1f GB of the %.1f GB available; streamed instead "
                    "(an eye pass every pass)",
                    kept / 1e9, available / 1e9);
      context.stats.skipped.push_back(why);
      return std::make_unique<StreamedHitPoints>(context);
    }
  }
  return std::make_unique<FixedHitPoints>(context);
}

}  // namespace ppm
