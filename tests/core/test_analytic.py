"""Scenes with known answers: the estimator's normalisation and convergence.

A point light of power Phi at the centre of a closed diffuse sphere of albedo
rho and radius R gives radiance rho Phi / (4 pi^2 R^2 (1 - rho)) on the whole
inner wall (direct plus every bounce). A diffuse plane under a point light has
radiance rho I cos(theta) / (pi d^2) with I = Phi / (4 pi).
"""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core

pytestmark = pytest.mark.accuracy


def closed_sphere_mean(passes, **settings):
    scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, **settings)
    renderer.run(passes=passes)
    return renderer.image()[..., :3]


EXPECTED = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0)


@pytest.mark.parametrize("threshold", [1, 10])
@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_closed_sphere_mean_within_one_percent(threshold, direct_light):
    image = closed_sphere_mean(60, threshold=threshold, direct_light=direct_light)
    assert np.all(np.isfinite(image))
    assert image.mean() == pytest.approx(EXPECTED, rel=0.01)


def test_closed_sphere_other_scales_and_albedos():
    # The answer scales as 1/R^2 and with rho/(1-rho): a wrong normalisation by
    # area, radius or photon count shows up here even if one case happened to fit.
    for radius, albedo in [(0.01, 0.3), (300.0, 0.7)]:
        scene = core_scenes.closed_sphere_with_point_light(radius=radius, albedo=albedo, power=50.0)
        renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, max_bounces=60)
        renderer.run(passes=60)
        expected = core_scenes.expected_closed_sphere_radiance(radius, albedo, 50.0)
        assert renderer.image()[..., :3].mean() == pytest.approx(expected, rel=0.015)


def test_error_decreases_with_passes():
    scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=5_000, threads=2, direct_light="photons", seed=3)
    errors = []
    for passes in (4, 16, 64, 256):
        renderer.run(passes=passes - renderer.stats()["passes"])
        image = renderer.image()[..., 0]
        errors.append(float(np.sqrt(np.mean((image - EXPECTED) ** 2))) / EXPECTED)
    assert errors == sorted(errors, reverse=True), errors
    assert errors[-1] < 0.5 * errors[0], errors


def plane_under_point_light(scale, offset, width=48, height=48, **settings):
    """Orthographic top view of a diffuse plane (albedo 0.5) lit by a point light
    at height h = scale above the origin, everything translated by `offset`."""
    scene = ppm_core.Scene()
    white = scene.add_material("plane", "diffuse", base_color=(0.5, 0.5, 0.5))
    s, o = scale, np.asarray(offset, dtype=float)
    corners = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], dtype=float) * s + o
    scene.add_mesh("plane", corners, np.array([[0, 1, 2], [0, 2, 3]]), materials=white)
    scene.add_light("point", name="lamp", power=100.0, position=o + np.array([0.0, 0.0, s]))
    camera = np.eye(4)
    camera[:3, 3] = o + np.array([0.0, 0.0, 3.0 * s])
    scene.set_camera(camera, width, height, projection="orthographic", ortho_scale=4.0 * s, clip_start=0.0)
    renderer = ppm_core.Renderer(scene, threads=2, **settings)
    renderer.run(passes=1)
    return renderer.image()[..., 0]


def plane_expected(scale, width=48, height=48, sub=8):
    """Pixel averages of rho I cos / (pi d^2), integrated on a sub x sub grid per pixel."""
    h = scale
    pixel = 4.0 * scale / width
    xs = (np.arange(width * sub) + 0.5) / sub * pixel - 2.0 * scale
    ys = (np.arange(height * sub) + 0.5) / sub * pixel - 2.0 * scale
    X, Y = np.meshgrid(xs, ys[::-1])  # top row first
    d2 = X**2 + Y**2 + h**2
    radiance = 0.5 / math.pi * (100.0 / (4.0 * math.pi)) * h / d2**1.5
    return radiance.reshape(height, sub, width, sub).mean(axis=(1, 3))


@pytest.mark.parametrize("scale,offset", [(1.0, (0, 0, 0)), (1e-3, (0, 0, 0)), (1e3, (0, 0, 0)),
                                          (1e-3, (1000.0, -2000.0, 500.0)), (10.0, (1e5, 0.0, 0.0))])
def test_plane_under_point_light_follows_cosine_law(scale, offset):
    # Exercises ray offsets: acne would darken pixels, a leak would brighten them.
    image = plane_under_point_light(scale, offset, photons_per_pass=1000, samples_per_pixel=64)
    expected = plane_expected(scale)
    assert np.all(np.isfinite(image))
    np.testing.assert_allclose(image, expected, rtol=0.01)


def test_sealed_box_lets_no_light_in():
    # A light outside a closed box, a camera inside: any light inside is a leak.
    scene = ppm_core.Scene()
    core_scenes.cornell_box(scene, size=2.0, with_front=True)
    scene.add_light("point", name="outside", power=1000.0, position=(0.0, 0.0, 2.0 + 1e-6))
    scene.set_camera(core_scenes.look_at((0.0, -0.5, 1.0), (0.0, 1.0, 1.0)), 32, 32)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2)
    renderer.run(passes=5)
    assert renderer.image()[..., :3].max() == 0.0
