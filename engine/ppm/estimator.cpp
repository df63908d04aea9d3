// The estimator for a render's settings (see estimator.h).
#include "ppm/estimator.h"

#include "ppm/fixed_hit_points.h"
#include "ppm/memory_budget.h"
#include "ppm/stochastic_hit_points.h"
#include "ppm/streamed_hit_points.h"

#include <cstdio>

namespace ppm {

std::unique_ptr<Estimator> make_estimator(RenderContext& context) {
  if (context.settings.hit_points == HitPointMode::Stochastic) return std::make_unique<StochasticHitPoints>(context);
  // Auto keeps them while they take at most half the memory available: the rest is the user's.
  const HitPointStorage storage = context.settings.hit_point_storage;
  const double kept = kept_hit_point_bytes(context.scene->camera(), context.settings.samples_per_pixel);
  const double available = static_cast<double>(available_memory_bytes());
  const bool too_large = available > 0.0 && kept > 0.5 * available;
  if (storage == HitPointStorage::Streamed || (storage == HitPointStorage::Auto && too_large)) {
    if (storage == HitPointStorage::Auto) {
      char why[200];
      std::snprintf(why, sizeof why,
                    "kept fixed hit points: would need about %.1f GB of the %.1f GB available; streamed instead "
                    "(an eye pass every pass)",
                    kept / 1e9, available / 1e9);
      context.stats.skipped.push_back(why);
    }
    return std::make_unique<StreamedHitPoints>(context);
  }
  return std::make_unique<FixedHitPoints>(context);
}

}  // namespace ppm
