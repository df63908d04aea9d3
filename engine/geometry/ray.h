// A ray and the record of where it hit. Directions are unit length.
#pragma once

#include "math/types.h"

namespace ppm {

struct Ray {
  Vec3 origin;
  Vec3 direction;
};

enum class PrimitiveKind : uint8_t { Triangle = 0, Sphere = 1, BezierRevolve = 2 };

struct Hit {
  double t = kInf;             // distance along the ray; kInf = no hit
  Vec3 position{0.0};
  Vec3 geometric_normal{0.0};  // unit, faces the side the primitive defines as outside
  Vec3 shading_normal{0.0};    // unit, interpolated normal (same side as geometric)
  Vec2 uv{0.0};
  uint32_t primitive = 0;      // index within the scene's primitive list
  uint32_t object = 0;         // id given by the caller when the object was added
  uint32_t material = 0;

  bool found() const { return t < kInf; }
};

}  // namespace ppm
