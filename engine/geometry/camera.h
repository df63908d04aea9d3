// The camera: Blender's conventions (looks down its local -Z, +Y up; the
// matrix is camera-to-world). The field of view or orthographic scale applies
// to the "fitted" image side chosen by `sensor_fit` (AUTO = the larger side);
// shift is in units of that side, as in Blender. Lens data (focus distance,
// aperture radius) is kept for depth of field.
#pragma once

#include "geometry/ray.h"

namespace ppm {

enum class Projection : uint8_t { Perspective, Orthographic };
enum class SensorFit : uint8_t { Auto, Horizontal, Vertical };

struct Camera {
  Mat4 camera_to_world{1.0};
  int width = 640, height = 480;
  Projection projection = Projection::Perspective;
  SensorFit sensor_fit = SensorFit::Auto;
  double fov = 0.8575560591178853;  // radians across the fitted side (Blender default 50 mm on 36 mm)
  double ortho_scale = 7.0;          // metres across the fitted side
  double shift_x = 0.0, shift_y = 0.0;
  double clip_start = 1e-3, clip_end = kInf;
  double focus_distance = 10.0;      // metres
  double aperture_radius = 0.0;      // metres; 0 = pinhole
  double focal_length = 0.0;         // metres, for the exact circle of confusion; 0 = focus >> focal length
  // Where this image (a render border's window) lies in the full frame, in pixels from its
  // bottom-left; a frame width of 0: the image is the frame. Only Window coordinates read it.
  int frame_x = 0, frame_y = 0, frame_width = 0, frame_height = 0;

  // The ray through image position (px, py) in pixels (x right, y up from the
  // bottom row). Its origin sits on the near clip plane.
  Ray generate_ray(double px, double py) const;
  // The same through a thin lens: (lens_u, lens_v) in [0,1)^2 pick a point on
  // the aperture disk; rays through one pixel meet on the focal plane.
  Ray generate_lens_ray(double px, double py, double lens_u, double lens_v) const;

  // Diameter in pixels of the circle of confusion of a point at depth z
  // (distance along the view axis), by the thin-lens equation.
  double coc_pixels(double z) const;
  // Distance along the view axis of a point.
  double depth_of(const Vec3& p) const { return glm::dot(p - position(), forward()); }

  // Cycles' camera space (Texture Coordinate's Camera): the camera's frame, +z looking forward.
  Vec3 camera_space(const Vec3& p) const;
  // Where p projects onto the full frame, 0..1 across it (Texture Coordinate's Window); z = 0.
  Vec3 window_coordinates(const Vec3& p) const;

  // Size of one pixel at distance 1 from a perspective camera, or in metres
  // for an orthographic one; sets the initial gather radius.
  double pixel_footprint() const;
  Vec3 position() const { return Vec3(camera_to_world[3]); }
  // Length of the ray direction's component along the view axis (for clipping and depth).
  Vec3 forward() const { return -glm::normalize(Vec3(camera_to_world[2])); }

 private:
  friend class CameraRays;
  double fitted_extent() const;  // size of the fitted side on the plane at distance 1 (or metres)
  bool fit_horizontal() const;
};

// The primary ray through every pixel centre, bottom row first (pixel x, y at y * width + x), as
// generate_ray makes it: 3 doubles of origin and 3 of direction each (Scene.camera_rays).
void pixel_centre_rays(const Camera& camera, double* origins, double* directions);

// A camera's rays with what is the same for all of them worked out once (the field of view's
// tangent, the axes): the eye pass makes millions.
class CameraRays {
 public:
  explicit CameraRays(const Camera& camera);
  Ray through(double px, double py) const;  // Camera::generate_ray
  Ray through_lens(double px, double py, double lens_u, double lens_v) const;  // Camera::generate_lens_ray

 private:
  const Camera& cam_;
  double extent_, pixel_;
  Vec3 origin_, right_, up_, back_, forward_;
};

}  // namespace ppm
