"""Camera projection (field of view, sensor fit, shift, orthographic) and texture
orientation, checked by where a small emissive marker lands in the image."""

import math

import numpy as np
import pytest

import ppm_core


def marker_scene(width, height, marker_xy, **camera):
    """An emissive 2 cm square at (x, y, -10) seen by a camera at the origin looking down -Z."""
    scene = ppm_core.Scene()
    glow = scene.add_material("glow", "emission", emission=(1.0, 1.0, 1.0))
    x, y = marker_xy
    s = 0.01
    quad = np.array([[x - s, y - s, -10], [x + s, y - s, -10], [x + s, y + s, -10], [x - s, y + s, -10]], float)
    scene.add_mesh("marker", quad, np.array([[0, 1, 2], [0, 2, 3]]), materials=glow)
    scene.set_camera(np.eye(4), width, height, **camera)
    return scene


def marker_pixel(scene):
    r = ppm_core.Renderer(scene, photons_per_pass=1, samples_per_pixel=16, threads=1)
    r.run(passes=1)
    img = r.image()[..., 0]
    ys, xs = np.nonzero(img > 0)
    assert len(xs) > 0, "marker not visible"
    w = img[ys, xs]
    return float((xs * w).sum() / w.sum()) + 0.5, float((ys * w).sum() / w.sum()) + 0.5


def expected_pixel(width, height, x, y, extent_fitted, fitted_size, shift=(0.0, 0.0), depth=10.0):
    # Image-plane position at unit distance, in pixels from the top-left corner.
    pixel = extent_fitted / fitted_size
    u = (x / depth - shift[0] * extent_fitted) / pixel + width / 2
    v = (y / depth - shift[1] * extent_fitted) / pixel + height / 2
    return u, height - v


@pytest.mark.parametrize("width,height,fit,fitted", [(200, 100, "auto", "w"), (100, 200, "auto", "h"),
                                                     (200, 100, "vertical", "h"), (100, 200, "horizontal", "w")])
def test_perspective_sensor_fit(width, height, fit, fitted):
    fov = math.radians(40)
    marker = (1.2, -0.7)
    scene = marker_scene(width, height, marker, fov=fov, sensor_fit=fit)
    got = marker_pixel(scene)
    want = expected_pixel(width, height, *marker, 2 * math.tan(fov / 2), width if fitted == "w" else height)
    assert got == pytest.approx(want, abs=0.3)


def test_perspective_shift():
    fov = math.radians(40)
    scene = marker_scene(200, 100, (0.5, 0.5), fov=fov, shift_x=0.1, shift_y=-0.05)
    want = expected_pixel(200, 100, 0.5, 0.5, 2 * math.tan(fov / 2), 200, shift=(0.1, -0.05))
    assert marker_pixel(scene) == pytest.approx(want, abs=0.3)


def test_orthographic():
    scene = marker_scene(160, 120, (1.5, -1.0), projection="orthographic", ortho_scale=8.0)
    pixel = 8.0 / 160
    want = (1.5 / pixel + 80, 120 - (-1.0 / pixel + 60))
    assert marker_pixel(scene) == pytest.approx(want, abs=0.3)


def test_texture_orientation_and_uvs():
    # A 16x16 texture in quadrants: bottom rows (row 0 first) red | green, top
    # rows blue | white, on a plane whose UVs span [0,1]^2 with u along +x and v along +y.
    tex = np.zeros((16, 16, 4), np.float32)
    tex[:8, :8, :3], tex[:8, 8:, :3] = (1, 0, 0), (0, 1, 0)
    tex[8:, :8, :3], tex[8:, 8:, :3] = (0, 0, 1), (1, 1, 1)
    tex[..., 3] = 1
    scene = ppm_core.Scene()
    t = scene.add_texture("checker", tex)
    mat = scene.add_material("textured", "diffuse", base_color=(1, 1, 1), texture=t)
    quad = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    scene.add_mesh("plane", quad, np.array([[0, 1, 2], [0, 2, 3]]), uvs=uvs, materials=mat)
    scene.set_background(1.0)
    cam = np.eye(4)
    cam[2, 3] = 1.0
    scene.set_camera(cam, 8, 8, projection="orthographic", ortho_scale=2.0, clip_start=0.0)
    r = ppm_core.Renderer(scene, photons_per_pass=1000, samples_per_pixel=4, threads=1)
    r.run(passes=4)
    img = r.image()[..., :3]  # top row first
    quadrant = lambda rows, cols: img[rows, cols].reshape(-1, 3).mean(axis=0)  # noqa: E731
    bottom_left, bottom_right = quadrant(slice(5, 8), slice(0, 3)), quadrant(slice(5, 8), slice(5, 8))
    top_left, top_right = quadrant(slice(0, 3), slice(0, 3)), quadrant(slice(0, 3), slice(5, 8))
    assert np.argmax(bottom_left) == 0 and bottom_left[1] < 0.1 * bottom_left[0]
    assert np.argmax(bottom_right) == 1 and bottom_right[0] < 0.1 * bottom_right[1]
    assert np.argmax(top_left) == 2 and top_left[0] < 0.1 * top_left[2]
    assert top_right.min() > 0.5 * top_right.max()
