// A ray and the record of where it hit. Directions are unit length.
#pragma once

#include "math/types.h"

namespace ppm {

// Cycles' ray visibility: each object and light says which kinds of ray see
// it, and a ray of one kind passes through what that kind does not see.
enum RayKind : uint8_t {
  kCameraRay = 1,
  kDiffuseRay = 2,        // after a diffuse bounce
  kGlossyRay = 4,         // after a reflection (mirror, metal, glass's reflected branch)
  kTransmissionRay = 8,   // after a refraction
  kShadowRay = 16,        // towards a light: shadow rays, and photons on their way from the light
};
constexpr uint8_t kAllRayKinds = 31;
// Not a ray kind: marks a primitive of a Holdout object in its visibility byte.
constexpr uint8_t kHoldoutFlag = 32;

struct Ray {
  Vec3 origin;
  Vec3 direction;
  uint8_t kind = kAllRayKinds;  // one RayKind; kAllRayKinds (queries from Python) sees everything visible at all
};

enum class PrimitiveKind : uint8_t { Triangle = 0, Sphere = 1, BezierRevolve = 2 };

struct Hit {
  double t = kInf;             // distance along the ray; kInf = no hit
  Vec3 position{0.0};
  Vec3 geometric_normal{0.0};  // unit, faces the side the primitive defines as outside
  Vec3 shading_normal{0.0};    // unit, interpolated normal (same side as geometric)
  Vec2 uv{0.0};
  glm::vec4 tangent{0.0f};     // a mesh's tangent (xyz) and bitangent sign (w); w = 0: none
  uint32_t primitive = 0;      // index within the scene's primitive list
  uint32_t object = 0;         // id given by the caller when the object was added
  uint32_t material = 0;

  bool found() const { return t < kInf; }
};

}  // namespace ppm
