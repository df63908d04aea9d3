"""Mixture materials (kind 'mixture': weighted lobes, layers) rendered through the whole pipeline:
they agree with the single-kind materials they reduce to, a white mixture of lossless lobes in a
white furnace stays white, and bad lobes are refused with a message."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core
from render_checks import EXPECTED_R1, finite_rgb

pytestmark = pytest.mark.accuracy


def closed_sphere_of(material_args, photons=20_000, passes=60, size=16, **settings):
    """The closed sphere with a point light inside (known answer for a diffuse wall), its wall
    `material_args`."""
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", **material_args)
    scene.add_sphere("room", (0.0, 0.0, 0.0), 1.0, wall)
    scene.add_light("point", name="lamp", power=100.0, position=(0.0, 0.0, 0.0))
    scene.set_camera(core_scenes.look_at((0.0, -0.1, 0.0), (0.0, 1.0, 0.0)), size, size, fov=math.radians(60),
                     clip_start=1e-3)
    renderer = ppm_core.Renderer(scene, photons_per_pass=photons, threads=2, seed=3, **settings)
    renderer.run(passes=passes)
    return finite_rgb(renderer)


def test_a_mixture_of_diffuse_lobes_is_the_diffuse_of_their_sum():
    lobes = [{"kind": "diffuse", "weight": 0.25, "color": 1.0}, {"kind": "diffuse", "weight": 0.5, "color": 0.5}]
    image = closed_sphere_of({"kind": "mixture", "lobes": lobes})
    assert image.mean() == pytest.approx(EXPECTED_R1, rel=0.01)


@pytest.mark.parametrize("hit_points", ["fixed", "stochastic"])
def test_half_mirror_half_diffuse_matches_the_analytic_sphere(hit_points):
    # A wall half white mirror, half diffuse of albedo 0.5 around a point light. Each bounce keeps
    # 0.75 of the light, so the irradiance is 4 E_d (E_d the direct one). The eye sees the diffuse
    # half, 0.5 * (0.5 / pi) * 4 E_d = E_d / pi, plus half of what the mirror shows: the wall across,
    # the same by symmetry. So L = 2 E_d / pi, twice the albedo-0.5 sphere's radiance. The eye pass
    # follows the mirror or stores a hit point at random, so fixed hit points need more pixels.
    lobes = [{"kind": "conductor", "weight": 0.5, "color": 1.0}, {"kind": "diffuse", "weight": 0.5, "color": 0.5}]
    size = 48 if hit_points == "fixed" else 16
    image = closed_sphere_of({"kind": "mixture", "lobes": lobes}, hit_points=hit_points, passes=60, size=size,
                             max_bounces=40)  # 0.75^12 of the light would be cut at the default 12
    assert image.mean() == pytest.approx(2.0 * EXPECTED_R1, rel=0.03)


def furnace(lobes, size=24, passes=30):
    """A ball of `lobes` in a white uniform world (radiance 1), filling the view."""
    scene = ppm_core.Scene()
    ball = scene.add_material("ball", "mixture", lobes=lobes)
    scene.add_sphere("ball", (0.0, 0.0, 0.0), 1.0, ball)
    scene.set_background((1.0, 1.0, 1.0))
    scene.set_camera(core_scenes.look_at((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)), size, size, fov=math.radians(12))
    renderer = ppm_core.Renderer(scene, photons_per_pass=50_000, threads=2, seed=1, max_bounces=64,
                                 hit_points="stochastic")
    renderer.run(passes=passes)
    return finite_rgb(renderer, hit_points=False)  # (glass is followed to the world)


@pytest.mark.parametrize("lobes", [
    [{"kind": "dielectric", "parts": "reflection", "layer": True, "roughness": 0.0, "ior": 1.5},
     {"kind": "diffuse", "color": 1.0}],
    [{"kind": "dielectric", "parts": "reflection", "layer": True, "roughness": 0.4, "ior": 1.5},
     {"kind": "diffuse", "color": 1.0}],
    [{"kind": "diffuse", "weight": 0.5, "color": 1.0}, {"kind": "dielectric", "weight": 0.3, "color": 1.0},
     {"kind": "transparent", "weight": 0.2, "color": 1.0}],
    [{"kind": "microfiber_sheen", "layer": True, "roughness": 0.5, "color": 1.0}, {"kind": "diffuse", "color": 1.0}],
    [{"kind": "dielectric", "roughness": 0.7, "ior": 1.5, "color": 1.0, "tint": 1.0, "multiscatter": True}],
], ids=["smooth layer over diffuse", "rough layer over diffuse", "diffuse, glass and transparent",
        "sheen layer over diffuse", "multiscatter rough glass"])
def test_white_lossless_mixtures_stay_white_in_a_white_furnace(lobes):
    image = furnace(lobes)
    centre = image[6:18, 6:18]  # well inside the ball's silhouette
    assert centre.mean() == pytest.approx(1.0, abs=0.03)


@pytest.mark.parametrize("lobes, message", [
    ([], "1 to 8 lobes"),
    ([{"kind": "diffuse"}] * 9, "1 to 8 lobes"),
    ([{"kind": "fur"}], "lobe kind"),
    ([{"kind": "diffuse", "weight": float("nan")}], "weight"),
    ([{"kind": "diffuse", "roughness": 2.0}], "roughness"),
    ([{"kind": "diffuse", "layer": True}], "layer"),
    ([{"kind": "diffuse", "colour": 1.0}], "unknown lobe key 'colour'"),
    ([{"kind": "diffuse", "beckmann": True}], "Beckmann"),
    ([{"kind": "glossy", "roughness": 0.5, "beckmann": True, "multiscatter": True}], "GGX's"),
    ([{"kind": "dielectric", "parts": "refraction", "multiscatter": True}], "multiscatter"),
    (["diffuse"], "dict"),
])
def test_bad_lobes_are_refused_with_a_message(lobes, message):
    scene = ppm_core.Scene()
    with pytest.raises(ValueError, match=message):
        scene.add_material("m", "mixture", lobes=lobes)


def test_lobes_belong_to_mixtures_only():
    with pytest.raises(ValueError, match="mixture"):
        ppm_core.Scene().add_material("m", "diffuse", lobes=[{"kind": "diffuse"}])


def test_a_constant_lambert_scene_is_untouched_by_mixtures():
    # The same scene, seed and settings give the same image whether or not another material of the
    # scene is a mixture nothing uses: mixtures add no random numbers to other materials' paths.
    def render(extra):
        scene = core_scenes.cornell_diffuse(32, 24)
        if extra:
            scene.add_material("unused", "mixture", lobes=[{"kind": "diffuse"}])
        r = ppm_core.Renderer(scene, photons_per_pass=5_000, threads=1, seed=2)
        r.run(passes=3)
        return np.asarray(r.image())

    assert np.array_equal(render(False), render(True))
