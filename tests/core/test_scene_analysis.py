"""Scene analysis (engine/ppm/scene_analysis.*): the work a scene cannot use is skipped, each skip
is named in stats()["skipped"], and skipping changes nothing in the image."""

import numpy as np
import pytest

import core_scenes
import ppm_core


def render(scene, passes=3, **settings):
    renderer = ppm_core.Renderer(scene, photons_per_pass=5_000, threads=2, seed=4, **settings)
    renderer.run(passes=passes)
    return renderer.image(), renderer.stats()


def skipped(stats, prefix):
    return [s for s in stats["skipped"] if s.startswith(prefix)]


def test_without_mirror_or_glass_the_eye_pass_follows_no_chains():
    scene = core_scenes.cornell_diffuse(32, 24)
    image, stats = render(scene)
    assert skipped(stats, "eye specular chains")
    everything, all_stats = render(core_scenes.cornell_diffuse(32, 24), scene_analysis=False)
    assert not skipped(all_stats, "eye specular chains")
    assert np.array_equal(image, everything)


def test_with_only_point_lights_fixed_hit_points_sample_direct_light_once():
    scene = core_scenes.cornell_3spheres(32, 24, light="point")
    image, stats = render(scene, passes=4, hit_points="fixed")
    assert skipped(stats, "direct light resampling") and stats["direct_samples"] == 1
    everything, all_stats = render(core_scenes.cornell_3spheres(32, 24, light="point"), passes=4,
                                   hit_points="fixed", scene_analysis=False)
    assert all_stats["direct_samples"] == 4
    np.testing.assert_allclose(image, everything, rtol=1e-12, atol=1e-15)  # the same sample, averaged


@pytest.mark.parametrize("hit_points", ["fixed", "stochastic"])
def test_an_area_light_is_sampled_every_pass(hit_points):
    image, stats = render(core_scenes.cornell_diffuse(32, 24), passes=3, hit_points=hit_points)
    assert not skipped(stats, "direct light resampling") and stats["direct_samples"] == 3


@pytest.mark.parametrize("hit_points", ["fixed", "stochastic"])
def test_without_anything_that_scatters_there_are_no_photon_passes(hit_points):
    """A mirror under a light: nothing diffuse or glossy receives photons."""
    scene = ppm_core.Scene()
    mirror = scene.add_material("mirror", "mirror")
    core_scenes.quad(scene, "floor", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], mirror)
    scene.add_light("point", position=(0, 0, 1))
    scene.set_camera(core_scenes.look_at((0, -2, 1), (0, 0, 0)), 512, 300)  # stochastic: 3 bands of rows
    _, stats = render(scene, passes=2, hit_points=hit_points)
    assert skipped(stats, "photon passes")
    assert stats["photons_emitted"] == 2 * 5_000  # an empty pass still counts its photons
    assert stats["photons_deposited"] == 0


def test_a_light_of_zero_power_is_left_out_of_sampling():
    scene = core_scenes.cornell_diffuse(16, 12)
    scene.add_light("point", name="off", power=0.0, position=(0.0, 0.5, 1.0))
    _, stats = render(scene, passes=1)
    assert skipped(stats, "zero-power lights: 1 left out")


def test_stats_say_whether_any_material_is_a_mixture():
    _, single = render(core_scenes.cornell_diffuse(32, 24))
    assert skipped(single, "mixture lobes")
    scene = core_scenes.cornell_diffuse(32, 24)
    scene.add_material("layered", "mixture", lobes=[{"kind": "diffuse"}])
    _, mixed = render(scene)
    assert not skipped(mixed, "mixture lobes")
