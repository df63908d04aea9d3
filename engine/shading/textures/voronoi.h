// Blender's Voronoi texture (Worley noise on a jittered grid of cells) as Cycles computes it:
// features F1, F2, Smooth F1, Distance to Edge and N-Sphere Radius in 1 to 4 dimensions, four
// distance metrics, and from 4.0 a fractal sum over octaves (detail, roughness, lacunarity).
#pragma once

#include "math/types.h"

namespace ppm::textures {

enum class VoronoiFeature : uint8_t { F1, F2, SmoothF1, DistanceToEdge, NSphereRadius };
enum class VoronoiMetric : uint8_t { Euclidean, Manhattan, Chebychev, Minkowski };

struct VoronoiSettings {
  int dimensions = 3;
  VoronoiFeature feature = VoronoiFeature::F1;
  VoronoiMetric metric = VoronoiMetric::Euclidean;
  bool normalize = false;
  bool pcg = false;  // newer Blender's integer cell hash (voronoi.cpp)
  float scale = 5.0f, detail = 0.0f, roughness = 0.5f, lacunarity = 2.0f, smoothness = 1.0f, exponent = 0.5f,
        randomness = 1.0f;
};

struct VoronoiResult {
  float distance = 0.0f;  // Distance (Distance to Edge: that; N-Sphere Radius: Radius)
  Vec3f color{0.0f};
  glm::vec4 position{0.0f};  // Position (xyz) and W
};

// At p (the node's vector and W, not yet scaled: 1-D (w, ...), 2-D/3-D the vector, 4-D (vector, w)).
VoronoiResult voronoi_texture(const VoronoiSettings& s, const glm::vec4& p);

}  // namespace ppm::textures
