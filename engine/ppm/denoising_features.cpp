// Denoising albedo and normal (see denoising_features.h).
#include "ppm/denoising_features.h"

#include "ppm/eye_pass.h"
#include "shading/closure.h"

#include <algorithm>

namespace ppm {

Color denoising_albedo(const Material& m, const SurfacePoint& sp, const Vec3& wo) {
  if (m.kind == MaterialKind::Mixture) return closure_albedo(m.lobes, sp, wo);
  return sp.albedo;  // diffuse, rough metal (F0), rough glass (its tint)
}

bool denoising_features(RenderContext& c, int samples_per_pixel, DenoisingFeatures& out, const Poll& poll) {
  const Camera& cam = c.scene->camera();
  const size_t pixels = static_cast<size_t>(cam.width) * cam.height;
  out.albedo.assign(pixels, Vec3f(0.0f));
  out.normal.assign(pixels, Vec3f(0.0f));
  EyePassOptions eye = c.eye_options(0, samples_per_pixel);
  eye.record_depth = false;
  eye.record_features = true;
  HitPoints band;
  EyePassScratch scratch;
  constexpr size_t kBandSamples = size_t(1) << 20;  // eye samples per band: bounded memory at any size
  const int rows = static_cast<int>(
      std::clamp<size_t>(kBandSamples / (size_t(cam.width) * samples_per_pixel), 1, size_t(cam.height)));
  for (int row = 0; row < cam.height; row += rows) {
    eye.row_begin = row;
    eye.row_end = std::min(cam.height, row + rows);
    if (!eye_pass(*c.scene, c.settings, eye, band, scratch, c.cancel, poll)) return false;
    const size_t first = static_cast<size_t>(row) * cam.width;
    std::copy(band.albedo.begin(), band.albedo.end(), out.albedo.begin() + first);
    std::copy(band.feature_normal.begin(), band.feature_normal.end(), out.normal.begin() + first);
  }
  return true;
}

}  // namespace ppm
