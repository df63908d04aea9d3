"""The eye pass (engine/ppm/eye_pass.*): camera rays go through mirror and glass chains to the first
surface that scatters, where they leave a hit point; what they see of emitters and the background on
the way goes straight into the pixel."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core


def facing_quad(material_args, width=8, height=6, samples=4, **settings):
    """A camera facing a large quad of the given material; a sun lights it."""
    scene = ppm_core.Scene()
    material = scene.add_material("surface", **material_args)
    core_scenes.quad(scene, "wall", [(-10, 5, -10), (10, 5, -10), (10, 5, 10), (-10, 5, 10)], material)
    scene.add_light("sun", power=2.0, direction=(0.0, 1.0, 0.0))
    scene.set_camera(core_scenes.look_at((0, 0, 0), (0, 1, 0)), width, height, fov=math.radians(30))
    renderer = ppm_core.Renderer(scene, photons_per_pass=1_000, threads=2, samples_per_pixel=samples,
                                 hit_points="fixed", **settings)
    renderer.run(passes=1)
    return renderer


def test_every_eye_sample_on_a_diffuse_surface_leaves_a_hit_point():
    renderer = facing_quad({"kind": "diffuse", "base_color": (0.5, 0.5, 0.5)}, samples=4)
    assert renderer.stats()["hit_points"] == 8 * 6 * 4
    # The sun straight behind the camera: radiance albedo / pi times its irradiance.
    np.testing.assert_allclose(renderer.image()[..., :3], 0.5 / math.pi * 2.0, rtol=1e-6)


def test_an_emitter_seen_directly_leaves_no_hit_point_and_shows_its_radiance():
    renderer = facing_quad({"kind": "emission", "base_color": (0, 0, 0), "emission": (3.0, 2.0, 1.0)})
    assert renderer.stats()["hit_points"] == 0
    np.testing.assert_allclose(renderer.image()[..., :3], np.broadcast_to((3.0, 2.0, 1.0), (6, 8, 3)), rtol=1e-6)


@pytest.mark.parametrize("max_bounces, lit", [(1, False), (2, True)])
def test_a_mirror_chain_ends_at_max_bounces(max_bounces, lit):
    """Camera -> mirror -> lit diffuse floor: the chain takes one bounce to reach the floor."""
    scene = ppm_core.Scene()
    mirror = scene.add_material("mirror", "mirror", base_color=(1.0, 1.0, 1.0))
    floor = scene.add_material("floor", "diffuse", base_color=(0.5, 0.5, 0.5))
    core_scenes.quad(scene, "mirror", [(-10, 5, -10), (10, 5, -10), (10, 5, 10), (-10, 5, 10)], mirror)
    core_scenes.quad(scene, "floor", [(-10, -10, -1), (10, -10, -1), (10, 10, -1), (-10, 10, -1)], floor)
    scene.add_light("sun", power=2.0, direction=(0.0, 0.0, -1.0))
    # Looking at the mirror from above, so that it reflects the floor.
    scene.set_camera(core_scenes.look_at((0, 0, 2), (0, 5, 0)), 8, 6, fov=math.radians(20))
    renderer = ppm_core.Renderer(scene, photons_per_pass=1_000, threads=2, max_bounces=max_bounces)
    renderer.run(passes=1)
    mean = renderer.image()[..., :3].mean()
    assert (mean > 0.1) == lit, mean
