"""Cycles' Emit and Env passes (Renderer.light_passes, settings light_passes): what camera rays see
at no bounce, the emission of surfaces and lights apart from the world; what mirrors show is in
neither, as Cycles counts it as glossy light. The same with every kind of hit points."""

import numpy as np
import pytest

import ppm_core
from core_scenes import look_at, quad

GLOW = (2.0, 1.0, 0.5)
SKY = (0.1, 0.2, 0.4)


def panel_scene():
    """Looking along +y: an emissive panel fills the left half of the view; in the lower right, a
    mirror tilted to show the sky; the world's colour wherever the view escapes."""
    scene = ppm_core.Scene()
    glow = scene.add_material("glow", "emission", emission=GLOW)
    mirror = scene.add_material("mirror", "mirror", base_color=(0.9, 0.9, 0.9))
    quad(scene, "panel", [(-3, 5, -3), (0, 5, -3), (0, 5, 3), (-3, 5, 3)], glow)
    # Facing the camera and up: the camera sees the sky in it.
    quad(scene, "mirror", [(0.2, 4.5, -3), (3, 4.5, -3), (3, 5.5, -0.2), (0.2, 5.5, -0.2)], mirror)
    scene.set_background(SKY)
    scene.set_camera(look_at((0, 0, 0), (0, 5, 0)), 32, 24, fov=1.2)
    return scene


@pytest.mark.parametrize("settings", [
    {"hit_points": "stochastic"},
    {"hit_points": "fixed"},
    {"hit_points": "fixed", "hit_point_storage": "streamed"},
], ids=["stochastic", "fixed", "streamed"])
def test_emit_and_env_are_what_camera_rays_see_directly(settings):
    renderer = ppm_core.Renderer(panel_scene(), photons_per_pass=2000, light_passes=True, threads=2, **settings)
    renderer.run(passes=2)
    passes, image = renderer.light_passes(), renderer.image()[..., :3]
    emit, env = passes["Emit"], passes["Env"]
    assert emit.shape == env.shape == (24, 32, 3)
    left, upper_right, lower_right = (slice(4, 20), slice(2, 12)), (slice(2, 8), slice(24, 30)), \
        (slice(15, 22), slice(19, 27))
    np.testing.assert_allclose(emit[left], np.broadcast_to(GLOW, emit[left].shape), rtol=1e-5)
    assert not env[left].any()
    np.testing.assert_allclose(env[upper_right], np.broadcast_to(SKY, env[upper_right].shape), rtol=1e-5)
    assert not emit[upper_right].any()
    # The sky seen in the mirror is in the image, but not in Env: Cycles counts it as glossy light.
    assert image[lower_right].mean() > 0.5 * np.mean(SKY) and not env[lower_right].any()
    assert np.all(emit + env <= image + 1e-5)


def test_light_passes_must_be_asked_for():
    renderer = ppm_core.Renderer(panel_scene(), photons_per_pass=2000)
    renderer.run(passes=1)
    with pytest.raises(RuntimeError, match="light_passes=True"):
        renderer.light_passes()
