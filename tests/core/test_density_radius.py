"""The initial gather radius follows the photon density where that, not the pixel, is the limit
(engine/ppm/photon_density_radius.h): a closed diffuse sphere around a point light has the same
radiance everywhere, seen through any lens (tests/blenders/lens_compare.py checks against Cycles)."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core

pytestmark = pytest.mark.accuracy

EXPECTED = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0)


def render(camera, mode="fixed", radius=1.0, passes=64, seed=1, size=16, **settings):
    """(pixel radiances / expected, stats) of the closed sphere seen through `camera`."""
    scene = core_scenes.closed_sphere_with_point_light(radius=radius, power=100.0 * radius**2)
    eye = core_scenes.look_at((0.0, -0.1 * radius, 0.0), (0.0, 1.0, 0.0))
    if camera[0] == "lens":
        scene.set_camera(eye, size, size, fov=2.0 * math.atan(18.0 / camera[1]))  # a 36 mm sensor
    else:
        scene.set_camera(eye, size, size, projection="orthographic", ortho_scale=camera[1] * radius)
    renderer = ppm_core.Renderer(scene, photons_per_pass=10_000, seed=seed, hit_points=mode,
                                 samples_per_pixel=1 if mode == "stochastic" else 4, **settings)
    renderer.run(passes=passes)
    return renderer.image()[..., :3].mean(axis=2) / EXPECTED, renderer.stats()


def mean_of_seeds(camera, **kwargs):
    """The image mean over three seeds: through a long lens every pixel sees the same few photons, so
    one render's error is one patch's (about 1/sqrt(4 photons x passes)), not an average over pixels."""
    images = [render(camera, seed=seed, **kwargs)[0] for seed in (1, 2, 3)]
    return float(np.mean(images)), max(float(i.max() / np.median(i)) for i in images)


CAMERAS = [("lens", 5.0), ("lens", 35.0), ("lens", 5000.0), ("ortho", 0.001)]


@pytest.mark.parametrize("mode", ["fixed", "stochastic"])
@pytest.mark.parametrize("camera", CAMERAS, ids=lambda c: f"{c[0]}-{c[1]:g}")
def test_any_lens_sees_the_analytic_radiance(camera, mode):
    mean, peak = mean_of_seeds(camera, mode=mode)
    assert mean == pytest.approx(1.0, abs=0.05)
    assert peak < 1.2  # no blotches


@pytest.mark.parametrize("radius", [1e-3, 1e4])
def test_tiny_and_huge_scenes_through_a_narrow_orthographic_window(radius):
    mean, peak = mean_of_seeds(("ortho", 0.001), radius=radius)
    assert mean == pytest.approx(1.0, abs=0.05) and peak < 1.2


def test_without_it_a_long_lens_loses_its_indirect_light():
    """What the spacing floor fixes (and that this test can tell): half the light, and blotches."""
    ratio, stats = render(("lens", 5000.0), density_radius=False)
    assert np.median(ratio) < 0.6 and ratio.max() > 2.0
    assert stats["photon_spacing"] == 0.0 and stats["radii_widened"] == 0


def test_radii_only_grow_and_only_where_photons_are_sparse():
    _, narrow = render(("lens", 5000.0), passes=1)
    _, narrow_off = render(("lens", 5000.0), passes=1, density_radius=False)
    assert narrow["radii_widened"] == narrow["hit_points"]  # every pixel is far below the photon spacing
    assert narrow["initial_radius_mean"] == pytest.approx(narrow["photon_spacing"])
    assert narrow["initial_radius_mean"] > 20 * narrow_off["initial_radius_mean"]
    _, wide = render(("lens", 5.0), passes=1)
    _, wide_off = render(("lens", 5.0), passes=1, density_radius=False)
    assert 0.0 < wide["photon_spacing"] < wide_off["initial_radius_mean"]
    assert wide["radii_widened"] == 0 and wide["initial_radius_mean"] == wide_off["initial_radius_mean"]


def test_the_default_scenes_are_unchanged():
    """At 640x480 the pixels, not the photons, limit the Cornell box's radii: nothing is widened."""
    scene = core_scenes.cornell_3spheres(width=160, height=120)
    renderer = ppm_core.Renderer(scene, photons_per_pass=200_000 // 16, seed=1)  # the same photons per pixel
    renderer.run(passes=1)
    stats = renderer.stats()
    assert stats["photon_spacing"] > 0.0 and stats["radii_widened"] == 0


def test_an_explicit_initial_radius_is_kept():
    _, stats = render(("lens", 5000.0), passes=1, initial_radius=1e-3)
    assert stats["radii_widened"] == 0 and stats["initial_radius_mean"] == pytest.approx(1e-3)
