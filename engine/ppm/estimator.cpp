// The estimator for a render's settings (see estimator.h).
#include "ppm/estimator.h"

#include "ppm/fixed_hit_points.h"
#include "ppm/stochastic_hit_points.h"

namespace ppm {

std::unique_ptr<Estimator> make_estimator(RenderContext& context) {
  if (context.settings.hit_points == HitPointMode::Stochastic) return std::make_unique<StochasticHitPoints>(context);
  return std::make_unique<FixedHitPoints>(context);
}

}  // namespace ppm
