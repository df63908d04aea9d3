"""Direct light (engine/ppm/direct_light.*): light sampling with shadow rays at the hit points. A
plane under a point light gets I cos / d^2 (the analytic answer is in test_analytic.py); here, what
shadow rays see: an occluder casts a hard black shadow, and a light that casts no shadow lights
through it."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core


def plane_with_occluder(cast_shadow):
    scene = ppm_core.Scene()
    white = scene.add_material("white", "diffuse", base_color=(0.5, 0.5, 0.5))
    black = scene.add_material("black", "diffuse", base_color=(0.0, 0.0, 0.0))
    core_scenes.quad(scene, "floor", [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], white)
    core_scenes.quad(scene, "card", [(-0.5, -0.5, 1), (0.5, -0.5, 1), (0.5, 0.5, 1), (-0.5, 0.5, 1)], black)
    scene.add_light("point", power=100.0, position=(0.0, 0.0, 2.0), cast_shadow=cast_shadow)
    # The camera, below the card, looks down at the floor: it sees the shadow, not the card.
    scene.set_camera(core_scenes.look_at((0.0, -4.0, 0.5), (0.0, 0.0, 0.0)), 32, 16, fov=math.radians(40))
    renderer = ppm_core.Renderer(scene, photons_per_pass=2_000, threads=2, samples_per_pixel=1, hit_points="fixed")
    renderer.run(passes=1)
    origins, directions = scene.camera_rays()
    hits = scene.intersect(origins, directions)
    points = origins + np.asarray(hits["t"])[:, None] * directions
    floor = np.isfinite(hits["t"]) & (np.abs(points[:, 2]) < 1e-6)
    # The shadow is |x|, |y| < 1 (the card projected from the light); pixels well inside it and well outside.
    umbra = floor & (np.abs(points[:, 0]) < 0.6) & (np.abs(points[:, 1]) < 0.6)
    lit = floor & ((np.abs(points[:, 0]) > 1.2) | (np.abs(points[:, 1]) > 1.2))
    image = renderer.image()[::-1, :, :3].reshape(-1, 3)  # bottom row first, like camera_rays
    return image, umbra, lit


def test_an_occluder_casts_a_hard_black_shadow():
    image, umbra, lit = plane_with_occluder(cast_shadow=True)
    assert umbra.sum() > 10 and lit.sum() > 10
    assert image[umbra].max() == 0.0
    assert image[lit].min() > 0.0


def test_a_light_that_casts_no_shadow_lights_through_the_occluder():
    image, umbra, _ = plane_with_occluder(cast_shadow=False)
    assert umbra.sum() > 10
    # Straight under the light the floor gets I / d^2 with I = 100 / (4 pi), d = 2: radiance 0.5/pi of it.
    expected = 0.5 / math.pi * 100.0 / (4.0 * math.pi) / 4.0
    assert image[umbra].max() == pytest.approx(expected, rel=0.05)
