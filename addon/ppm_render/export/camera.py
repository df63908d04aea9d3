"""Blender camera -> core camera, as Cycles interprets it (blender/camera.cpp).

Field of view from lens and sensor (sensor fit AUTO measures the sensor width
across the larger image side), orthographic scale, shift in units of the
fitted side, clipping, and depth-of-field data (focus distance or a focus
object's distance along the view axis; aperture radius = lens * 1e-3 /
(2 f-stop), 1 / (2 f-stop) for orthographic cameras).

A render border is rendered as a smaller camera whose pixels are the same as
the full frame's: same pixel footprint, shifted to the border's centre.

Like Cycles, any object can be the scene camera: one that is not a camera (an
Empty, a light) is looked through with Cycles' default lens data.
"""

import math
from types import SimpleNamespace

import numpy as np

MAX_COORDINATE = 1e30  # metres, the core's limit

# Cycles' lens data for a scene camera that is not a camera (blender_camera_init in blender/camera.cpp).
CYCLES_DEFAULT_LENS = SimpleNamespace(
    type="PERSP", lens=50.0, sensor_width=36.0, sensor_height=24.0, sensor_fit="AUTO", shift_x=0.0, shift_y=0.0,
    clip_start=1e-5, clip_end=1e5,
    dof=SimpleNamespace(use_dof=False, focus_object=None, focus_distance=10.0, aperture_fstop=0.0))


class Frame:
    """Pixel sizes of one render: the full frame and the window actually rendered."""

    def __init__(self, width, height, x=0, y=0, window_width=None, window_height=None):
        self.width, self.height = width, height
        self.x, self.y = x, y  # window origin in pixels from the bottom-left
        self.window_width = width if window_width is None else window_width
        self.window_height = height if window_height is None else window_height

    @classmethod
    def from_render_settings(cls, render):
        """The sizes of Blender's render result, in Blender's own arithmetic (render_init_from_main):
        the percentage in integers, the border's edges as float32 products truncated, so that the
        image always fills the result Blender made."""
        width = max(1, render.resolution_x * render.resolution_percentage // 100)
        height = max(1, render.resolution_y * render.resolution_percentage // 100)
        if not render.use_border:
            return cls(width, height)
        x0, x1 = _border_pixel(render.border_min_x, width), _border_pixel(render.border_max_x, width)
        y0, y1 = _border_pixel(render.border_min_y, height), _border_pixel(render.border_max_y, height)
        return cls(width, height, x0, y0, max(1, x1 - x0), max(1, y1 - y0))


def _border_pixel(fraction, size):
    """Blender's `(int)(border * size)` with a float border: the product rounded to float32 first
    (0.35 * 720 is 251.99999 in double and 252 in float)."""
    return int(np.float32(fraction) * np.float32(size))


def _fit_horizontal(sensor_fit, width, height):
    if sensor_fit == "HORIZONTAL":
        return True
    if sensor_fit == "VERTICAL":
        return False
    return width >= height


def _fitted_extent(cam, fit_horizontal):
    """Width of the fitted image side on the plane at distance 1 (or in metres for ortho)."""
    if cam.type == "ORTHO":
        return cam.ortho_scale
    sensor = cam.sensor_height if cam.sensor_fit == "VERTICAL" else cam.sensor_width
    return sensor / cam.lens  # = 2 tan(fov / 2)


def _camera_to_world(matrix):
    """World matrix without scale (Cycles ignores a camera's scale). An axis scaled to zero (or
    flattened onto another) is rebuilt square to the others; a camera scaled to zero on every axis
    keeps the world's orientation."""
    m = np.array(matrix, dtype=float)
    axes = m[:3, :3].T.copy()  # rows: x, y, z
    lengths = np.linalg.norm(axes, axis=1)
    ok = np.isfinite(lengths) & (lengths > 1e-300)
    axes[ok] /= lengths[ok, None]
    if ok.sum() < 3:
        axes = _complete_axes(axes, ok)
    m[:3, :3] = axes.T
    return m


def _complete_axes(axes, ok):
    """A right-handed orthonormal frame that keeps the usable axes, preferring the view axis z."""
    known = [i for i in (2, 1, 0) if ok[i]]
    if not known:
        return np.eye(3)
    first = known[0]
    helper = np.eye(3)[int(np.argmin(np.abs(axes[first])))]
    second = next((i for i in known[1:] if np.linalg.norm(np.cross(axes[first], axes[i])) > 1e-9), None)
    other = axes[second] if second is not None else helper
    frame = np.eye(3)
    frame[first] = axes[first]
    j, k = (first + 1) % 3, (first + 2) % 3  # cyclic: axis_k = axis_first x axis_j
    if second == k:
        frame[k] = other - np.dot(other, axes[first]) * axes[first]
        frame[k] /= np.linalg.norm(frame[k])
        frame[j] = np.cross(frame[k], frame[first])
    else:
        frame[j] = other - np.dot(other, axes[first]) * axes[first]
        frame[j] /= np.linalg.norm(frame[j])
        frame[k] = np.cross(frame[first], frame[j])
    return frame


def focus_distance(cam, matrix):
    """Cycles' focus distance: the focus object's distance along the view axis, else dof.focus_distance."""
    dof = cam.dof
    if dof.focus_object is None:
        return float(dof.focus_distance)
    m = _camera_to_world(matrix)
    target = np.array(dof.focus_object.matrix_world.translation, dtype=float)
    return float(abs(np.dot(target - m[:3, 3], -m[:3, 2])))


def aperture_radius(cam):
    dof = cam.dof
    if not dof.use_dof or dof.aperture_fstop <= 0.0:
        return 0.0
    if cam.type == "ORTHO":
        return 1.0 / (2.0 * dof.aperture_fstop)
    return cam.lens * 1e-3 / (2.0 * dof.aperture_fstop)


def window_of(frame, pixel, extent, shift_x, shift_y):
    """(width, shift_x, shift_y) of `frame`'s window as a camera of its own, fitted horizontally with
    the full frame's pixel size `pixel`: its width on the image plane (in the units of `extent`, the
    full frame's fitted side) and its centre's shifts in units of that width."""
    cx = (frame.x + 0.5 * frame.window_width - 0.5 * frame.width) * pixel + shift_x * extent
    cy = (frame.y + 0.5 * frame.window_height - 0.5 * frame.height) * pixel + shift_y * extent
    window_extent = pixel * frame.window_width
    return window_extent, cx / window_extent, cy / window_extent


def camera_arguments(camera_object, frame, warn, dof_mode="OFF", view=None):
    """Keyword arguments for Scene.set_camera for `frame` (full frame or border window).

    The aperture goes to the core only when scene.ppm.dof_mode asks for depth of field. `view`:
    (matrix_world, shift_x) of one view of a stereo or multi-view render (RenderEngine's
    camera_model_matrix and camera_shift_x), in place of the camera's own.
    """
    matrix_world = camera_object.matrix_world if view is None else view[0]
    if camera_object.type == "CAMERA":
        cam = camera_object.data
    else:
        cam = CYCLES_DEFAULT_LENS
        warn(f"scene camera '{camera_object.name}' is {camera_object.type.lower()}, not a camera: looking through "
             "it with Cycles' default lens (50 mm, 36 mm sensor)")
    if cam.type == "PANO":
        warn(f"camera '{camera_object.name}': panoramic cameras are not supported; rendered as perspective")
    fit_h = _fit_horizontal(cam.sensor_fit, frame.width, frame.height)
    extent = _fitted_extent(cam, fit_h)
    pixel = extent / (frame.width if fit_h else frame.height)
    shift_x = cam.shift_x if view is None else view[1]
    window_extent, window_shift_x, window_shift_y = window_of(frame, pixel, extent, shift_x, cam.shift_y)
    position = np.array(matrix_world.translation, dtype=float)
    if not (np.isfinite(position).all() and np.abs(position).max() <= MAX_COORDINATE):
        raise ValueError(f"camera '{camera_object.name}' is at {tuple(position)}, not a point the core can render "
                         f"from (coordinates up to {MAX_COORDINATE:g} m)")
    args = {
        "matrix": _camera_to_world(matrix_world),
        "width": frame.window_width,
        "height": frame.window_height,
        "sensor_fit": "horizontal",
        "shift_x": window_shift_x,
        "shift_y": window_shift_y,
        "clip_start": float(cam.clip_start),
        "clip_end": float(cam.clip_end),
        "focus_distance": max(focus_distance(cam, matrix_world), 1e-6),
        "aperture_radius": aperture_radius(cam) if dof_mode != "OFF" else 0.0,
        "frame": (frame.x, frame.y, frame.width, frame.height),  # Window coordinates span the full frame
    }
    if cam.type == "ORTHO":
        args.update(projection="orthographic", ortho_scale=window_extent)
    else:
        args.update(projection="perspective", fov=2.0 * math.atan(0.5 * window_extent),
                    focal_length=float(cam.lens) * 1e-3)
    return args
