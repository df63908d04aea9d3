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


def glossy_ball(light, followed_light="mis", roughness=0.4, seed=3, occluded=False):
    """A glossy ball (a lobe eye paths follow, as every glossy one) lit by `light` beside the camera,
    against black."""
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
        scene.add_light("sun", power=3.0, direction=direction, angle=math.radians(30))
    elif light == "spot":
        scene.add_light("spot", power=500.0, position=position, direction=direction, spot_angle=math.radians(40))
    elif light == "sphere":
        scene.add_light("sphere", power=500.0, position=position, radius=1.0)
    elif light == "rectangle":
        scene.add_light("rectangle", power=500.0, position=position, direction=direction, size=(2.0, 1.5))
    else:
        scene.add_light("point", power=500.0, position=position)
    scene.set_camera(core_scenes.look_at((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)), 48, 48, fov=math.radians(45))
    # Nothing else in the scene: photons bring the ball nothing (a few keep the pass whole), and the
    # passes are its eye samples.
    renderer = ppm_core.Renderer(scene, photons_per_pass=1_000, threads=2, seed=seed, hit_points="stochastic",
                                 followed_light=followed_light)
    renderer.run(passes=128)
    return renderer.image()[..., :3]


def ggx_plane_under_point(size, scale, roughness, height, power, albedo):
    """Radiance a glossy plane (constant reflectance `albedo`, GGX, Smith masking) reflects straight
    up from a point light `height` above its origin, averaged over each of `size` x `size` pixels of
    a square window `scale` wide (4 x 4 points a pixel)."""
    a2 = roughness ** 4  # alpha = roughness^2
    steps = (np.arange(size * 4) + 0.5) / (size * 4) * scale - scale / 2
    x, y = np.meshgrid(steps, steps)
    d2 = x * x + y * y + height * height
    cos_i = height / np.sqrt(d2)
    half = np.stack([-x, -y, height + np.sqrt(d2)])  # wi + wo, wo straight up
    cos_h2 = half[2] ** 2 / (half ** 2).sum(axis=0)
    d = a2 / (math.pi * (cos_h2 * (a2 - 1.0) + 1.0) ** 2)
    tan2_i = (1.0 - cos_i ** 2) / cos_i ** 2
    g2 = 1.0 / (1.0 + (-1.0 + np.sqrt(1.0 + a2 * tan2_i)) / 2.0)  # Lambda of wo (straight up) is 0
    radiance = albedo * d * g2 / (4.0 * cos_i) * cos_i * power / (4.0 * math.pi * d2)
    return radiance.reshape(size, 4, size, 4).mean(axis=(1, 3))


def test_a_glossy_plane_reflects_a_point_light_as_ggx_does():
    # No direction an eye path draws from a glossy lobe meets a point light (a glossy ball of
    # roughness 0.1 under one rendered black): light sampling alone brings it. Straight down through
    # an orthographic window: every pixel against the analytic reflection.
    size, scale, roughness, height = 24, 3.0, 0.5, 1.5
    scene = ppm_core.Scene()
    plane = scene.add_material("plane", "mixture", lobes=[{"kind": "glossy", "color": 0.8, "roughness": roughness}])
    core_scenes.quad(scene, "plane", [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], plane)
    scene.add_light("point", power=300.0, position=(0.0, 0.0, height))
    # Looking straight down from below the light (which casts no shadow on the camera: it has no body).
    scene.set_camera(core_scenes.look_at((0.0, 0.0, 1.0), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0)), size, size,
                     projection="orthographic", ortho_scale=scale)
    renderer = ppm_core.Renderer(scene, photons_per_pass=1_000, threads=2, seed=2, hit_points="stochastic")
    renderer.run(passes=256)
    image = renderer.image()[..., 0]
    expected = ggx_plane_under_point(size, scale, roughness, height, 300.0, 0.8)
    assert expected.max() > 1.0
    np.testing.assert_allclose(image, expected, rtol=0.02, atol=1e-3 * expected.max())


@pytest.mark.parametrize("light", ["sphere", "rectangle", "sun_disc"])
def test_light_sampling_and_the_lobes_own_draw_agree_and_share_the_light(light):
    # Each technique alone (followed_light 'lights', 'draws') and both weighed (the default) render
    # the same highlight: the weights of a direction both can draw sum to one. Lights large enough
    # for the draws alone to converge; the spread over seeds 1-4 of each ratio is within 1.5%.
    mis, lights, draws = (glossy_ball(light, mode).mean() for mode in ("mis", "lights", "draws"))
    assert mis > 0.01
    assert lights == pytest.approx(mis, rel=0.03)
    assert draws == pytest.approx(mis, rel=0.03)


@pytest.mark.parametrize("light", ["point", "spot", "sun"])
def test_lights_of_no_size_reach_the_lobes_eye_paths_follow_through_their_shadows(light):
    lit = glossy_ball(light)
    assert lit.mean() > 0.01
    assert glossy_ball(light, followed_light="draws").max() == 0.0  # what the draws alone see of it
    assert glossy_ball(light, occluded=True).max() == 0.0  # its shadow rays see the card
