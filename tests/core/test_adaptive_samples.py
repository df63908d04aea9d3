"""Adaptive eye sampling with stochastic hit points (engine/ppm/adaptive_samples.h): noisy pixels
get more eye samples per pass once the error estimate has passes enough, and the image converges to
the same answer. Whether it pays at equal time: bench/README.md, "Adaptive eye sampling"."""

import pytest

import core_scenes
import ppm_core

SPHERE_RADIANCE = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0)


def luminance(rgba):
    return rgba[..., 0] * 0.2126 + rgba[..., 1] * 0.7152 + rgba[..., 2] * 0.0722


def test_noisy_pixels_get_more_eye_samples_after_the_first_passes():
    scene = core_scenes.cornell_3spheres(64, 48)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=3, hit_points="stochastic",
                                 adaptive_samples=4, error_min_passes=4)
    renderer.run(passes=4)
    uniform = renderer.stats()["hit_points"]  # hit points of the last pass: one eye sample a pixel
    renderer.run(passes=1)
    adaptive = renderer.stats()["hit_points"]
    # Only pixels noisier than the average get more (measured: 34 more hit points, at the lamp's and
    # the spheres' edges); none gets more than 4.
    assert uniform < adaptive < 4 * uniform, (uniform, adaptive)


def test_the_closed_sphere_converges_to_its_radiance_with_adaptive_samples():
    scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=5, hit_points="stochastic",
                                 adaptive_samples=8)
    renderer.run(passes=40)
    assert luminance(renderer.image()).mean() == pytest.approx(SPHERE_RADIANCE, rel=0.01)


@pytest.mark.accuracy
def test_more_samples_in_a_pixel_do_not_shrink_its_radius_faster():
    """The radius update sees the photons of the pixel's mean sample: with more eye samples a pass the
    radii shrink as with one (measured: 0.04287 against 0.04292, with 49% more hit points)."""
    radius, hit_points = {}, {}
    for samples in (1, 4):
        scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
        renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=1, seed=5, hit_points="stochastic",
                                     adaptive_samples=samples)
        renderer.run(passes=40)
        radius[samples], hit_points[samples] = renderer.stats()["radius_mean"], renderer.stats()["hit_points"]
    assert hit_points[4] > 1.2 * hit_points[1]
    assert radius[4] == pytest.approx(radius[1], rel=0.03)


@pytest.mark.parametrize("bad", [0, 65])
def test_bad_adaptive_samples_are_refused(bad):
    with pytest.raises(ValueError, match="adaptive_samples"):
        ppm_core.Renderer(core_scenes.cornell_diffuse(16, 12), adaptive_samples=bad)
