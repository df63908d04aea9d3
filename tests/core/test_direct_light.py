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


def glossy_ball(roughness, light, occluded=False, seed=3):
    """A glossy ball of `roughness` (below kFollowedRoughness, 0.25, eye paths follow its lobe; above,
    hit points gather it) lit by a light of no size beside the camera, against black."""
    scene = ppm_core.Scene()
    ball = scene.add_material("ball", "mixture", lobes=[{"kind": "glossy", "color": 0.8, "roughness": roughness}])
    scene.add_sphere("ball", (0.0, 0.0, 0.0), 1.0, ball)
    if occluded:  # a card between the light and the ball, behind the camera
        card = scene.add_material("card", "diffuse", base_color=(0.0, 0.0, 0.0))
        core_scenes.quad(scene, "card", [(-3, -3.5, -3), (5, -3.5, -3), (5, -3.5, 5), (-3, -3.5, 5)], card)
    position, direction = (1.5, -4.0, 1.5), (-1.5, 4.0, -1.5)
    if light == "sun":
        scene.add_light("sun", power=3.0, direction=direction)
    elif light == "sun_disc":
        scene.add_light("sun", power=3.0, direction=direction, angle=math.radians(10))
    elif light == "spot":
        scene.add_light("spot", power=500.0, position=position, direction=direction, spot_angle=math.radians(40))
    elif light == "sphere":
        scene.add_light("sphere", power=500.0, position=position, radius=0.3)
    elif light == "rectangle":
        scene.add_light("rectangle", power=500.0, position=position, direction=direction, size=(0.8, 0.4))
    else:
        scene.add_light("point", power=500.0, position=position)
    scene.set_camera(core_scenes.look_at((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)), 64, 64, fov=math.radians(45))
    # Nothing else in the scene: photons bring the ball nothing (a few keep the pass whole), and the
    # passes are its eye samples.
    renderer = ppm_core.Renderer(scene, photons_per_pass=1_000, threads=2, seed=seed, hit_points="stochastic")
    renderer.run(passes=160)
    return renderer.image()[..., :3]


@pytest.mark.parametrize("light", ["point", "spot", "sun", "sphere", "rectangle", "sun_disc"])
def test_a_lobe_eye_paths_follow_reflects_lights_as_a_gathered_one_does(light):
    # No sampled direction meets a light of no size, and no hit point is stored on a lobe the eye
    # follows: its highlight was black. Lights with a size were met by sampled directions alone
    # (noisy where they are small); now sampled too, the two weighed by the balance heuristic. The
    # highlight is the one a gathered lobe just above the threshold shows (the same total over the
    # image: the lobes are alike).
    followed, gathered = glossy_ball(0.24, light), glossy_ball(0.26, light)
    assert gathered.mean() > 0.01
    # Lights of no size: light sampling alone on either side, within 0.5% over seeds 1-4. Lights with
    # a size: a small highlight, sampled by a light sample a pass on the gathered side; the ratio
    # spreads by 1.5% over seeds 1-4 (a light met twice, or not weighed, would be 20-100% off).
    tolerance = 0.01 if light in ("point", "spot", "sun") else 0.05
    assert followed.mean() == pytest.approx(gathered.mean(), rel=tolerance)
    assert glossy_ball(0.23, light, occluded=True).max() == 0.0  # its shadow rays see the card
