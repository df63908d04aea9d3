// An object's info for node programs (shading/node_program.h's ObjectInfo) from what Blender gives:
// its object-to-world matrix and its texture space.
#pragma once

#include "math/types.h"
#include "shading/node_program.h"

namespace ppm {

// The matrices, location and texture space of an ObjectInfo; the rest (Random, Pass Index, Color,
// attributes) as ObjectInfo's defaults. An object scaled to nothing along an axis (it renders, flat)
// has no inverse: its coordinates are then measured from its origin along the world's axes. A
// texture space of size 0 along an axis is 1 there, as Blender makes a flat one's.
ObjectInfo object_info(const Mat4& object_to_world, const Vec3& texspace_location, const Vec3& texspace_size);

}  // namespace ppm
