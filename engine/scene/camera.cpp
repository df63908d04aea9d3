// Primary ray generation (see camera.h).
#include "scene/camera.h"

namespace ppm {

bool Camera::fit_horizontal() const {
  if (sensor_fit == SensorFit::Horizontal) return true;
  if (sensor_fit == SensorFit::Vertical) return false;
  return width >= height;
}

double Camera::fitted_extent() const {
  return projection == Projection::Perspective ? 2.0 * std::tan(0.5 * fov) : ortho_scale;
}

double Camera::pixel_footprint() const {
  return fitted_extent() / (fit_horizontal() ? width : height);
}

Ray Camera::generate_ray(double px, double py) const {
  // Image-plane coordinates in units of the fitted extent, centred, plus shift.
  const double extent = fitted_extent();
  const double pixel = pixel_footprint();
  const double x = (px - 0.5 * width) * pixel + shift_x * extent;
  const double y = (py - 0.5 * height) * pixel + shift_y * extent;
  const Vec3 right = Vec3(camera_to_world[0]), up = Vec3(camera_to_world[1]), back = Vec3(camera_to_world[2]);
  const Vec3 origin = position();
  Ray ray;
  if (projection == Projection::Perspective) {
    const Vec3 local = Vec3(x, y, -1.0);
    const Vec3 d = glm::normalize(local.x * right + local.y * up + local.z * back);
    const double along = 1.0 / glm::length(local);  // cos of the angle to the view axis
    ray.origin = origin + d * (clip_start / along);
    ray.direction = d;
  } else {
    ray.direction = -glm::normalize(back);
    ray.origin = origin + x * glm::normalize(right) + y * glm::normalize(up) + ray.direction * clip_start;
  }
  return ray;
}

}  // namespace ppm
