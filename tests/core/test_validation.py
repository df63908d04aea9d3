"""Bad input raises a Python exception that names the object and the field; nothing crashes."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core

TRI = np.array([[0, 1, 2]])
POS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)


@pytest.fixture
def scene():
    s = ppm_core.Scene()
    s.add_material("white")
    return s


@pytest.mark.parametrize(
    "kwargs,message",
    [
        (dict(positions=np.array([[0, 0, 0], [1, math.nan, 0], [0, 1, 0]])), "position 1 is not finite"),
        (dict(triangles=np.array([[0, 1, 7]])), "uses vertex 7"),
        (dict(triangles=np.zeros((0, 3), dtype=int)), "has no triangles"),
        (dict(triangles=np.array([[0, 1]])), "shape (T, 3)"),
        (dict(positions=np.zeros((3, 2))), "positions must have shape (N, 3)"),
        (dict(materials=5), "material index 5 out of range"),
        (dict(materials=np.array([0, 0])), "one per triangle"),
        (dict(normals=np.array([[0, 0, 1]])), "normals"),
        (dict(normals=np.full((3, 3), np.inf)), "normals contain NaN or Inf"),
        (dict(uvs=np.zeros((2, 2))), "uvs"),
        (dict(triangles=np.array([[0, 1, -1]])), "out of range"),
    ],
)
def test_bad_mesh(scene, kwargs, message):
    args = dict(name="teapot", positions=POS, triangles=TRI)
    args.update(kwargs)
    with pytest.raises(ValueError) as err:
        scene.add_mesh(**args)
    assert "mesh 'teapot'" in str(err.value) and message in str(err.value)


@pytest.mark.parametrize(
    "call,message",
    [
        (lambda s: s.add_sphere("ball", (0, 0, math.nan), 1.0, 0), "center is not finite"),
        (lambda s: s.add_sphere("ball", (0, 0, 0), -1.0, 0), "radius must be a positive"),
        (lambda s: s.add_sphere("ball", (0, 0, 0), 1.0, 3), "material index 3"),
        (lambda s: s.add_sphere("ball", (0, 0), 1.0, 0), "center must be 3 numbers"),
        (lambda s: s.add_sphere("sun", (0, 0, 0), 1.0, s.add_material("hot", emission=1.0)),
         "supported on meshes only"),
        (lambda s: s.add_material("m", "plastic"), "kind must be one of"),
        (lambda s: s.add_material("m", roughness=2.0), "roughness must be in [0, 1]"),
        (lambda s: s.add_material("m", ior=0.0), "ior must be a positive"),
        (lambda s: s.add_material("m", base_color=(1, -1, 1)), "negative component"),
        (lambda s: s.add_material("m", emission=(math.inf, 0, 0)), "emission is not finite"),
        (lambda s: s.add_material("m", texture=4), "texture index out of range"),
        (lambda s: s.add_texture("t", np.zeros((4, 4, 2))), "shape (H, W, 4) or (H, W, 3)"),
        (lambda s: s.add_texture("t", np.full((2, 2, 4), np.nan)), "NaN or Inf"),
        (lambda s: s.add_light("laser"), "kind must be one of"),
        (lambda s: s.add_light("point", power=-5.0), "power has a negative component"),
        (lambda s: s.add_light("point", position=(0, math.nan, 0)), "position is not finite"),
        (lambda s: s.add_light("rectangle", size=0.0), "size must be positive"),
        (lambda s: s.add_light("spot", spot_angle=0.0), "spot_angle"),
        (lambda s: s.add_light("sun", angle=4.0), "angle must be in"),
        (lambda s: s.add_light("sphere", radius=0.0), "radius must be a positive"),
        (lambda s: s.add_light("spot", direction=(0, 0, 0)), "direction must be non-zero"),
        (lambda s: s.set_camera(np.eye(4), 0, 10), "width and height must be positive"),
        (lambda s: s.set_camera(np.eye(3), 10, 10), "matrix must be a 4x4 matrix"),
        (lambda s: s.set_camera(np.full((4, 4), np.nan), 10, 10), "NaN or Inf"),
        (lambda s: s.set_camera(np.eye(4), 10, 10, fov=4.0), "fov must be in"),
        (lambda s: s.set_camera(np.eye(4), 10, 10, projection="fisheye"), "projection must be one of"),
        (lambda s: s.set_camera(np.zeros((4, 4)), 10, 10), "matrix is singular"),
        (lambda s: s.set_background((math.nan, 0, 0)), "background"),
        (lambda s: s.intersect(np.zeros((1, 3)), np.zeros((1, 3))), "direction 0 is zero"),
        (lambda s: s.intersect(np.zeros((2, 3)), np.ones((1, 3))), "same length"),
        (lambda s: s.intersect(np.zeros((1, 3)), np.ones((1, 3)), threads=-1), "threads must be >= 0"),
    ],
)
def test_bad_builder_calls(scene, call, message):
    with pytest.raises(ValueError) as err:
        call(scene)
    assert message in str(err.value)


def small_scene():
    return core_scenes.closed_sphere_with_point_light(width=8, height=8)


@pytest.mark.parametrize(
    "settings,message",
    [
        (dict(photons_per_pass=0), "photons_per_pass must be at least 1"),
        (dict(alpha=1.0), "alpha must be in (0, 1)"),
        (dict(threshold=0), "threshold must be at least 1"),
        (dict(samples_per_pixel=0), "samples_per_pixel"),
        (dict(initial_radius=-1.0), "initial_radius"),
        (dict(grid="octree"), "grid must be one of"),
        (dict(photon_count=5), "unknown setting 'photon_count'"),
        (dict(alpha="high"), "alpha has the wrong type"),
    ],
)
def test_bad_settings(settings, message):
    with pytest.raises(ValueError) as err:
        ppm_core.Renderer(small_scene(), **settings)
    assert message in str(err.value)


def test_settings_object_and_defaults():
    defaults = ppm_core.default_settings()
    assert defaults["threshold"] == 30 and defaults["threads"] == 0
    s = ppm_core.Settings(alpha=0.6, grid="hash")
    assert s.alpha == 0.6 and s.grid == "hash"
    r = ppm_core.Renderer(small_scene(), s, threshold=3)
    assert r.settings["alpha"] == 0.6 and r.settings["threshold"] == 3
    with pytest.raises(ValueError, match="unknown setting"):
        ppm_core.Settings(alhpa=0.5)


def test_renderer_needs_a_camera_and_run_needs_a_limit():
    scene = ppm_core.Scene()
    scene.add_material("white")
    scene.add_sphere("ball", (0, 0, 0), 1.0, 0)
    with pytest.raises(ValueError, match="no camera"):
        ppm_core.Renderer(scene)
    with pytest.raises(ValueError, match="passes > 0 or seconds > 0"):
        ppm_core.Renderer(small_scene()).run()


def test_scene_is_frozen_while_a_renderer_uses_it():
    scene = small_scene()
    renderer = ppm_core.Renderer(scene, threads=1, photons_per_pass=100)
    with pytest.raises(RuntimeError, match="while a Renderer uses it"):
        scene.add_sphere("late", (0, 0, 0), 0.1, 0)
    del renderer
    scene.add_sphere("late", (0, 0, 0), 0.1, 0)  # allowed again


def test_empty_and_degenerate_scenes_render_black():
    scene = ppm_core.Scene()
    scene.add_material("white")
    scene.set_camera(np.eye(4), 8, 8)
    renderer = ppm_core.Renderer(scene, photons_per_pass=100)
    renderer.run(passes=2)
    assert renderer.image()[..., :3].max() == 0.0
    # Zero-area triangles and a zero-power light: no crash, no NaN.
    scene = ppm_core.Scene()
    scene.add_material("white")
    scene.add_mesh("flat", np.zeros((3, 3)), TRI)
    scene.add_light("point", power=0.0, position=(0, 0, 1))
    scene.set_camera(np.eye(4), 8, 8)
    renderer = ppm_core.Renderer(scene, photons_per_pass=100)
    renderer.run(passes=2)
    assert np.isfinite(renderer.image()).all()
    assert any("zero-power" in s for s in renderer.stats()["skipped"])
