// An object's matrices and texture space for node programs.
#include "scene/object_info.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace ppm {

ObjectInfo object_info(const Mat4& object_to_world, const Vec3& texspace_location, const Vec3& texspace_size) {
  ObjectInfo info;
  info.object_to_world = object_to_world;
  info.location = Vec3(info.object_to_world[3]);
  const double det = glm::determinant(info.object_to_world);
  info.world_to_object = std::fabs(det) > 0.0 && std::isfinite(det) ? glm::inverse(info.object_to_world)
                                                                    : glm::translate(Mat4(1.0), -info.location);
  Vec3 size = texspace_size;
  for (int k = 0; k < 3; ++k)
    if (size[k] == 0.0) size[k] = 1.0;
  info.texspace_min = texspace_location - size;
  info.texspace_size = 2.0 * size;
  return info;
}

}  // namespace ppm
