"""Photon guiding (settings photon_guiding, engine/ppm/photon_guide.h): guided lights learn where
their photons are seen and send more there, and the image keeps its known answers (the photons'
flux is divided by the guide's density)."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core
from core_scenes import look_at, quad


def render(scene, passes, **settings):
    renderer = ppm_core.Renderer(scene, threads=2, seed=4, hit_points="stochastic",
                                 **{"photons_per_pass": 20_000, **settings})
    renderer.run(passes=passes)
    return renderer


@pytest.mark.accuracy
@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_a_guided_closed_sphere_keeps_its_known_radiance(direct_light):
    scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
    image = render(scene, 60, photon_guiding=True, direct_light=direct_light).image()[..., :3]
    assert image.mean() == pytest.approx(core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0), rel=0.01)


def lamp_over_floor():
    """A point light 1 m over a white floor, seen from above: photons sent upwards are lost."""
    scene = ppm_core.Scene()
    floor = scene.add_material("floor", "diffuse", base_color=(0.8, 0.8, 0.8))
    quad(scene, "floor", [(-20, -20, 0), (20, -20, 0), (20, 20, 0), (-20, 20, 0)], floor)
    scene.add_light("point", name="lamp", power=100.0, position=(0.0, 0.0, 1.0))
    scene.set_camera(look_at((0.0, -0.01, 3.0), (0.0, 0.0, 0.0)), 24, 24, fov=math.radians(60))
    return scene


def test_the_guide_learns_where_photons_are_seen_and_stays_unbiased():
    # Photons carry direct light here, so the floor gathers those that head down.
    guided = render(lamp_over_floor(), 12, photon_guiding=True, direct_light="photons")
    plain = render(lamp_over_floor(), 12, direct_light="photons")
    (probabilities,) = guided.photon_guide()
    assert probabilities.shape == (16, 32) and probabilities.sum() == pytest.approx(1.0)
    # Rings run from cos(theta) = -1 (straight down) up: uniformly, half would head down.
    downwards = probabilities[:8].sum()
    assert downwards > 0.8, downwards
    # Most of all towards what the camera sees, below the lamp.
    assert probabilities[0].sum() > 2.0 * probabilities[7].sum()
    assert guided.image()[..., :3].mean() == pytest.approx(plain.image()[..., :3].mean(), rel=0.01)


def test_area_lights_are_guided_over_their_front_side():
    guided = render(core_scenes.cornell_diffuse(48, 36), 12, photon_guiding=True)
    plain = render(core_scenes.cornell_diffuse(48, 36), 12)
    (probabilities,) = guided.photon_guide()
    assert probabilities.max() > 1.5 / probabilities.size  # it has learned
    assert guided.image()[..., :3].mean() == pytest.approx(plain.image()[..., :3].mean(), rel=0.01)


def test_guiding_is_deterministic_and_the_guide_starts_uniform():
    first = render(core_scenes.cornell_3spheres(40, 30), 4, photon_guiding=True)
    second = render(core_scenes.cornell_3spheres(40, 30), 4, photon_guiding=True)
    np.testing.assert_array_equal(first.image(), second.image())
    fresh = ppm_core.Renderer(core_scenes.cornell_3spheres(40, 30), photon_guiding=True, photons_per_pass=1000)
    fresh.run(passes=1)
    np.testing.assert_allclose(fresh.photon_guide()[0], 1.0 / 512)
    assert render(core_scenes.cornell_3spheres(40, 30), 1).photon_guide() == []


def test_guiding_needs_passes_that_learn_from_each_other():
    with pytest.raises(ValueError, match="photon_guiding"):
        ppm_core.Renderer(core_scenes.cornell_3spheres(16, 12), photon_guiding=True, hit_points="stochastic",
                          radius_schedule="global")
