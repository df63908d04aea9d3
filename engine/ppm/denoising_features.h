// Cycles' Denoising Albedo and Denoising Normal, the guides Blender's Denoise node (Intel Open Image
// Denoise) takes with the image. As Cycles writes them, an eye sample's features are those of the
// first surface its path does not follow as a mirror or smooth glass: the albedo there times the
// path's throughput (the mirrors' and glass's tint and Fresnel weight), and the surface's normal
// facing the viewer; background and emitters add nothing. Our eye chains stop exactly at the
// surfaces where hit points are recorded, so the features are an eye pass's (eye_pass.h,
// record_features), made band by band and then dropped. Eye paths also follow glossy and glass
// lobes, rough ones too: as Cycles, they write the albedo of those rougher than 0.075
// (Lobe::rough_for_denoising) where they meet them, and write nothing more after drawing one.
#pragma once

#include "math/types.h"
#include "ppm/render_context.h"
#include "scene/material.h"
#include "shading/scatter.h"

#include <vector>

namespace ppm {

// The albedo of what a hit point stores of material `m` at `sp`, seen from `wo`.
Color denoising_albedo(const Material& m, const SurfacePoint& sp, const Vec3& wo);

// Per pixel, row 0 at the bottom: albedo (linear RGB) and normal (world space, a mean of unit
// normals over the pixel's samples: shorter where samples disagree or see no surface).
struct DenoisingFeatures {
  std::vector<Vec3f> albedo, normal;
};

// `samples_per_pixel` jittered eye samples per pixel, as the render's own eye pass draws them
// (lens, bounce limits, seed). False if cancelled.
bool denoising_features(RenderContext& context, int samples_per_pixel, DenoisingFeatures& out,
                        const Poll& poll);

}  // namespace ppm
