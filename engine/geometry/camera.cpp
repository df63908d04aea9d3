// Primary ray generation (see camera.h).
#include "geometry/camera.h"

#include "math/sampling.h"

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

Ray Camera::generate_ray(double px, double py) const { return CameraRays(*this).through(px, py); }

Ray Camera::generate_lens_ray(double px, double py, double lens_u, double lens_v) const {
  return CameraRays(*this).through_lens(px, py, lens_u, lens_v);
}

CameraRays::CameraRays(const Camera& camera)
    : cam_(camera),
      extent_(camera.fitted_extent()),
      pixel_(camera.pixel_footprint()),
      origin_(camera.position()),
      right_(camera.camera_to_world[0]),
      up_(camera.camera_to_world[1]),
      back_(camera.camera_to_world[2]),
      forward_(camera.forward()) {}

Ray CameraRays::through(double px, double py) const {
  // Image-plane coordinates in units of the fitted extent, centred, plus shift.
  const double x = (px - 0.5 * cam_.width) * pixel_ + cam_.shift_x * extent_;
  const double y = (py - 0.5 * cam_.height) * pixel_ + cam_.shift_y * extent_;
  Ray ray;
  if (cam_.projection == Projection::Perspective) {
    const Vec3 local = Vec3(x, y, -1.0);
    const Vec3 d = glm::normalize(local.x * right_ + local.y * up_ + local.z * back_);
    const double along = 1.0 / glm::length(local);  // cos of the angle to the view axis
    ray.origin = origin_ + d * (cam_.clip_start / along);
    ray.direction = d;
  } else {
    ray.direction = -glm::normalize(back_);
    ray.origin = origin_ + x * glm::normalize(right_) + y * glm::normalize(up_) + ray.direction * cam_.clip_start;
  }
  return ray;
}

Ray CameraRays::through_lens(double px, double py, double lens_u, double lens_v) const {
  Ray pinhole = through(px, py);
  if (cam_.aperture_radius <= 0.0 || cam_.projection != Projection::Perspective) return pinhole;
  // Where the pinhole ray meets the plane of focus.
  const double t_focus = cam_.focus_distance / glm::dot(pinhole.direction, forward_);
  const Vec3 focus_point = origin_ + pinhole.direction * t_focus;
  const Vec2 d = sample_uniform_disk(lens_u, lens_v) * cam_.aperture_radius;
  const Vec3 lens_point = origin_ + d.x * right_ + d.y * up_;
  Ray ray;
  ray.direction = glm::normalize(focus_point - lens_point);
  ray.origin = lens_point + ray.direction * (cam_.clip_start / glm::dot(ray.direction, forward_));
  return ray;
}

Vec3 Camera::camera_space(const Vec3& p) const {
  const Vec3 d = p - position();  // the axes are orthonormal (Scene::set_camera)
  return Vec3(glm::dot(d, Vec3(camera_to_world[0])), glm::dot(d, Vec3(camera_to_world[1])),
              -glm::dot(d, Vec3(camera_to_world[2])));
}

Vec3 Camera::window_coordinates(const Vec3& p) const {
  const Vec3 local = camera_space(p);
  double x = local.x, y = local.y;
  if (projection == Projection::Perspective) {
    if (local.z == 0.0) return Vec3(0.0);  // Cycles' perspective divide gives 0 there
    x /= local.z;  // behind the camera this mirrors, as Cycles' divide does
    y /= local.z;
  }
  // Inverse of generate_ray's image-plane mapping, then the window's place in the frame.
  const double extent = fitted_extent(), pixel = pixel_footprint();
  const double px = (x - shift_x * extent) / pixel + 0.5 * width + frame_x;
  const double py = (y - shift_y * extent) / pixel + 0.5 * height + frame_y;
  const bool whole = frame_width <= 0 || frame_height <= 0;
  return Vec3(px / (whole ? width : frame_width), py / (whole ? height : frame_height), 0.0);
}

double Camera::coc_pixels(double z) const {
  if (aperture_radius <= 0.0 || projection != Projection::Perspective || !(z > 0.0)) return 0.0;
  // Sensor CoC = A f / (S - f) * |z - S| / z; in pixels divide by the sensor
  // pixel size, f * extent / size. Without f, S >> f is assumed.
  const double S = focus_distance;
  const double thin = focal_length > 0.0 && focal_length < S ? S / (S - focal_length) : 1.0;
  const double pixels_per_radian = 1.0 / pixel_footprint();
  return 2.0 * aperture_radius * thin * std::fabs(1.0 / S - 1.0 / z) * pixels_per_radian;
}

void pixel_centre_rays(const Camera& camera, double* origins, double* directions) {
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Ray ray = camera.generate_ray(x + 0.5, y + 0.5);
      const size_t i = 3 * (static_cast<size_t>(y) * camera.width + x);
      for (int k = 0; k < 3; ++k) origins[i + k] = ray.origin[k], directions[i + k] = ray.direction[k];
    }
}

}  // namespace ppm
