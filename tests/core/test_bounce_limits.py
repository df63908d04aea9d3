"""Cycles' light-path limits (light_path_limits with total/diffuse/glossy/transmission/volume_bounces)
and a light's or the world's own max_bounces, against answers known in closed form.

In a closed diffuse sphere of albedo rho and radius R with a point light of power Phi at its centre,
a path that may continue from at most D diffuse scatterings sees the wall at radiance
rho Phi / (4 pi^2 R^2) (1 + rho + ... + rho^D): direct light plus D interreflections.
"""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core

RHO, POWER = 0.5, 100.0


def truncated_sphere_radiance(bounces):
    return RHO * POWER / (4.0 * math.pi**2) * sum(RHO**k for k in range(bounces + 1))


def closed_sphere_mean(light_max_bounces=1024, passes=40, **settings):
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", "diffuse", base_color=(RHO, RHO, RHO))
    scene.add_sphere("room", (0.0, 0.0, 0.0), 1.0, wall)
    scene.add_light("point", name="lamp", power=POWER, position=(0.0, 0.0, 0.0), max_bounces=light_max_bounces)
    scene.set_camera(core_scenes.look_at((0.0, -0.1, 0.0), (0.0, 1.0, 0.0)), 32, 32, fov=math.radians(60))
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, **settings)
    renderer.run(passes=passes)
    return float(renderer.image()[..., :3].mean())


@pytest.mark.parametrize("bounces", [0, 1, 3])
def test_diffuse_bounces_truncate_the_interreflections(bounces):
    mean = closed_sphere_mean(light_path_limits=True, diffuse_bounces=bounces)
    assert mean == pytest.approx(truncated_sphere_radiance(bounces), rel=0.015)


@pytest.mark.accuracy
@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_total_bounces_and_a_lights_own_limit_truncate_alike(direct_light):
    expected = truncated_sphere_radiance(2)
    by_total = closed_sphere_mean(light_path_limits=True, total_bounces=2, diffuse_bounces=100,
                                  direct_light=direct_light)
    by_light = closed_sphere_mean(light_max_bounces=2, direct_light=direct_light)
    assert by_total == pytest.approx(expected, rel=0.015)
    assert by_light == pytest.approx(expected, rel=0.015)


def test_limits_nothing_reaches_change_nothing():
    kwargs = dict(passes=4, seed=7)
    unlimited = closed_sphere_mean(**kwargs)
    # The limits replace max_bounces (12) by total_bounces: with total 11 the paths are as long.
    assert closed_sphere_mean(light_path_limits=True, total_bounces=11, diffuse_bounces=1024, **kwargs) == unlimited
    assert closed_sphere_mean(light_max_bounces=1024, **kwargs) == unlimited


def glass_ball_over_a_lit_floor(transmission_bounces, glossy_bounces=4):
    """A camera looking down through a smooth glass ball at a lit floor: the floor seen through the
    ball takes two transmissions."""
    scene = ppm_core.Scene()
    floor = scene.add_material("floor", "diffuse", base_color=(0.8, 0.8, 0.8))
    glass = scene.add_material("glass", "glass", base_color=(1.0, 1.0, 1.0), ior=1.5)
    scene.add_mesh("floor", np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], float),
                   np.array([[0, 1, 2], [0, 2, 3]]), materials=floor)
    scene.add_sphere("ball", (0.0, 0.0, 1.0), 0.5, glass)
    scene.add_light("sun", name="sun", power=3.0, direction=(0.3, 0.2, -1.0))
    scene.set_camera(core_scenes.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0)), 32, 32,
                     fov=math.radians(20))
    renderer = ppm_core.Renderer(scene, photons_per_pass=5_000, threads=2, light_path_limits=True,
                                 transmission_bounces=transmission_bounces, glossy_bounces=glossy_bounces)
    renderer.run(passes=2)
    return renderer.image()[12:20, 12:20, :3].mean()  # the middle of the ball


def test_transmission_bounces_end_eye_paths_through_glass():
    through = glass_ball_over_a_lit_floor(2)
    # One transmission leaves only the ball's reflections (about 4% of the floor's light).
    assert glass_ball_over_a_lit_floor(1) < 0.1 * through
    assert through > 0.0


def mirror_ball_under_the_world(world_max_bounces):
    scene = ppm_core.Scene()
    mirror = scene.add_material("mirror", "mirror", base_color=(1.0, 1.0, 1.0))
    scene.add_sphere("ball", (0.0, 0.0, 0.0), 1.0, mirror)
    scene.set_background((0.2, 0.4, 0.6), max_bounces=world_max_bounces)
    scene.set_camera(core_scenes.look_at((0.0, -5.0, 0.0), (0.0, 0.0, 0.0)), 16, 16, fov=math.radians(10))
    renderer = ppm_core.Renderer(scene, photons_per_pass=1_000, threads=2)
    renderer.run(passes=1)
    return renderer.image()[6:10, 6:10, :3].mean(axis=(0, 1))


def test_the_worlds_own_limit_hides_it_from_reflections():
    assert mirror_ball_under_the_world(1024) == pytest.approx((0.2, 0.4, 0.6), rel=1e-3)
    assert np.all(mirror_ball_under_the_world(0) == 0.0)


@pytest.mark.parametrize("name", ["total_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                                  "volume_bounces"])
@pytest.mark.parametrize("value", [-1, 1025])
def test_limits_out_of_range_are_refused(name, value):
    scene = core_scenes.closed_sphere_with_point_light()
    with pytest.raises(ValueError, match="bounces must be in"):
        ppm_core.Renderer(scene, **{name: value})


@pytest.mark.parametrize("value", [-1, 1025])
def test_a_lights_limit_out_of_range_is_refused(value):
    scene = ppm_core.Scene()
    with pytest.raises(ValueError, match="lamp.*max_bounces"):
        scene.add_light("point", name="lamp", position=(0, 0, 0), max_bounces=value)
    with pytest.raises(ValueError, match="max_bounces"):
        scene.set_background((1, 1, 1), max_bounces=value)


FOG_SIGMA_S, FOG_SIGMA_A, FOG_LIGHT = 0.45, 0.05, np.array([0.8, 0.2, 0.3])


def fog_scene(size):
    """A world of fog of albedo 0.9 around a point light just outside the view (test_media's single
    scattering scene, ten times as thick and scattering most of what it meets)."""
    scene = ppm_core.Scene()
    scene.add_medium("fog", sigma_a=FOG_SIGMA_A, sigma_s=FOG_SIGMA_S)
    scene.set_world_medium("fog")
    scene.add_light("point", power=POWER, position=tuple(FOG_LIGHT))
    scene.set_camera(core_scenes.look_at((0.0, -2.0, 0.0), (0.0, 0.0, 0.0)), size, size, fov=0.6)
    return scene


def fog_image_sum(size, passes, **settings):
    renderer = ppm_core.Renderer(fog_scene(size), hit_points="stochastic", photons_per_pass=2000, threads=2, seed=3,
                                 **settings)
    renderer.run(passes=passes)
    return float(renderer.image()[..., :3].mean(axis=2).sum())


@pytest.mark.accuracy
@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_volume_bounces_0_leaves_single_scattering(direct_light):
    """Cycles' default Volume bounces, 0: a path continues from no scattering in a medium, so the fog
    shows single scattering alone, the integral along each ray (test_media.single_scattering), where
    without the limit multiple scattering makes it 2.4 times as bright; one bounce lies between
    (1.6 times). Seeds 3 and 5 at 200 passes: light sampling's sum 1.003 and 1.018 of the integral;
    photons' 1.062 and (seed 4, 800 passes) 1.063, their gather spheres' bias near the lamp."""
    from test_media import single_scattering

    size, sub = 8, 4
    origins, directions = fog_scene(size * sub).camera_rays()
    expected = single_scattering(origins, directions, FOG_LIGHT, POWER / (4 * math.pi), FOG_SIGMA_S,
                                 FOG_SIGMA_S + FOG_SIGMA_A, steps=4000)
    expected = expected.reshape(size, sub, size, sub).mean(axis=(1, 3))[::-1].sum()  # top row first
    limited = dict(direct_light=direct_light, light_path_limits=True, total_bounces=64)
    single = fog_image_sum(size, 200, volume_bounces=0, **limited) / expected
    assert single == pytest.approx(1.0, abs=0.03 if direct_light == "sampled" else 0.09)
    once = fog_image_sum(size, 200, volume_bounces=1, **limited) / expected
    unlimited = fog_image_sum(size, 200, direct_light=direct_light) / expected
    assert 1.4 < once < 1.8 and unlimited > 2.2


@pytest.mark.accuracy
@pytest.mark.parametrize("radius", [0.05, 0.02])
def test_beams_carry_single_scattering_as_the_integral(radius):
    """The same fog with Volume bounces 0 and photons carrying the direct light too: the image is
    single scattering carried by photon beams alone (straight from the lamp, they are specular
    chains of no bounce), gathered by each camera ray's segment (volume_beams), and compared with
    the integral along the rays. Seed 3, 400 passes: 0.998 and 0.995 of it at 0.05 and 0.02 m
    (volume photons gathered by points: 1.042 and 1.272, at 0.02 m a ball holds a photon now and
    then)."""
    from test_media import single_scattering

    size, sub = 8, 4
    origins, directions = fog_scene(size * sub).camera_rays()
    expected = single_scattering(origins, directions, FOG_LIGHT, POWER / (4 * math.pi), FOG_SIGMA_S,
                                 FOG_SIGMA_S + FOG_SIGMA_A, steps=4000)
    expected = expected.reshape(size, sub, size, sub).mean(axis=(1, 3))[::-1].sum()
    limited = dict(direct_light="photons", light_path_limits=True, total_bounces=64, volume_bounces=0)
    got = fog_image_sum(size, 400, initial_radius=radius, volume_beams=True, **limited) / expected
    assert got == pytest.approx(1.0, abs=0.03)
