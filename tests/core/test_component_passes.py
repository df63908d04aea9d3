"""Cycles' light passes (Renderer.component_passes, settings component_passes): Diffuse, Glossy
and Transmission Direct, Indirect and Color, and the caustic part. They add up to the image with
Emit and Env, split light as Cycles files it (by the first surface's lobe class, or by the chain's
first bounce through mirrors and glass), and match known answers in the closed sphere."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core
from core_scenes import look_at, quad

LIGHT_PASSES = ["DiffDir", "DiffInd", "GlossDir", "GlossInd", "TransDir", "TransInd"]
ESTIMATORS = [
    {"hit_points": "stochastic"},
    {"hit_points": "stochastic", "radius_schedule": "global"},
    {"hit_points": "fixed"},
]
ESTIMATOR_IDS = ["stochastic", "global", "fixed"]


def render(scene, passes=4, **settings):
    renderer = ppm_core.Renderer(scene, threads=2, seed=5, component_passes=True, light_passes=True,
                                 **{"photons_per_pass": 20_000, **settings})
    renderer.run(passes=passes)
    return renderer


@pytest.mark.parametrize("settings", ESTIMATORS, ids=ESTIMATOR_IDS)
def test_the_passes_add_up_to_the_image(settings):
    renderer = render(core_scenes.cornell_3spheres(64, 48), **settings)
    image, seen, parts = renderer.image()[..., :3], renderer.light_passes(), renderer.component_passes()
    total = seen["Emit"] + seen["Env"] + sum(parts[name] for name in LIGHT_PASSES)
    np.testing.assert_allclose(total, image, atol=1e-6 * image.max())
    for name, values in parts.items():
        assert values.shape == (48, 64, 3) and np.all(np.isfinite(values)) and values.min() >= 0.0, name
    # The mirror ball and the glass ball file what they show as glossy and transmission light.
    for name in ["DiffDir", "DiffInd", "GlossInd", "TransInd", "DiffCol", "GlossCol", "TransCol", "Caustic"]:
        assert parts[name].max() > 0.0, name
    indirect = parts["DiffInd"] + parts["GlossInd"] + parts["TransInd"]
    assert np.all(parts["Caustic"] <= indirect + 1e-6 * image.max())


def closed_sphere(lobes, size=12):
    """A closed sphere (radius 1) of `lobes` with a 100 W point light at its centre."""
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", "mixture", lobes=lobes)
    scene.add_sphere("room", (0.0, 0.0, 0.0), 1.0, wall)
    scene.add_light("point", name="lamp", power=100.0, position=(0.0, 0.0, 0.0))
    scene.set_camera(look_at((0.0, -0.1, 0.0), (0.0, 1.0, 0.0)), size, size, fov=math.radians(60), clip_start=1e-3)
    return scene


@pytest.mark.parametrize("settings", ESTIMATORS, ids=ESTIMATOR_IDS)
def test_closed_sphere_direct_and_indirect_have_their_known_values(settings):
    # Albedo rho: direct light rho E / pi with E = P / (4 pi r^2); indirect rho / (1 - rho) times that.
    rho, irradiance = 0.5, 100.0 / (4.0 * math.pi)
    parts = render(closed_sphere([{"kind": "diffuse", "weight": 1.0, "color": rho}]), passes=30,
                   **settings).component_passes()
    np.testing.assert_allclose(parts["DiffCol"], rho, rtol=1e-6)
    np.testing.assert_allclose(parts["DiffDir"], rho * irradiance / math.pi, rtol=1e-5)
    assert parts["DiffInd"].mean() == pytest.approx(rho / (1 - rho) * rho * irradiance / math.pi, rel=0.03)
    for name in ["GlossDir", "GlossInd", "TransDir", "TransInd", "VolumeDir", "VolumeInd", "Caustic", "GlossCol",
                 "TransCol"]:
        assert not parts[name].any(), name


def test_a_mixture_splits_its_light_by_lobe_class():
    diffuse = {"kind": "diffuse", "weight": 0.5, "color": 1.0}
    glossy = {"kind": "glossy", "weight": 0.5, "color": 1.0, "roughness": 0.6}
    mixed = render(closed_sphere([diffuse, glossy]), passes=6).component_passes()
    plain = render(closed_sphere([{"kind": "diffuse", "weight": 1.0, "color": 0.5}]), passes=6).component_passes()
    np.testing.assert_allclose(mixed["DiffCol"], 0.5, rtol=1e-6)
    np.testing.assert_allclose(mixed["GlossCol"], 0.5, rtol=1e-6)
    # The same direct light through the diffuse lobe as through a plain diffuse wall of half the
    # colour: on average, as eye samples store the diffuse lobe or follow the glossy one at random
    # (a pixel whose few samples all followed it has none; 0.7% apart over the image with seed 5).
    assert mixed["DiffDir"].mean() == pytest.approx(plain["DiffDir"].mean(), rel=0.03)
    for name in ("GlossDir", "GlossInd"):  # nearly every pixel has samples that followed the glossy lobe
        assert (mixed[name] > 0.0).mean() > 0.8, name
    assert not mixed["TransDir"].any() and not mixed["TransInd"].any()


GLOW = np.array([2.0, 1.0, 0.5])


def test_a_mirror_files_what_it_shows_as_glossy():
    """A mirror filling the view shows, behind the camera, an emissive panel above (Glossy Direct)
    and a diffuse wall below lit by a point light (Glossy Indirect: light after two scatterings)."""
    scene = ppm_core.Scene()
    mirror = scene.add_material("mirror", "mirror", base_color=(0.9, 0.9, 0.9))
    glow = scene.add_material("glow", "emission", emission=tuple(GLOW))
    wall = scene.add_material("wall", "diffuse", base_color=(0.5, 0.5, 0.5))
    quad(scene, "mirror", [(-4, 5, -4), (4, 5, -4), (4, 5, 4), (-4, 5, 4)], mirror)
    quad(scene, "panel", [(-4, -1, 0.2), (-4, -1, 4), (4, -1, 4), (4, -1, 0.2)], glow)
    quad(scene, "wall", [(-4, -1, -4), (-4, -1, -0.2), (4, -1, -0.2), (4, -1, -4)], wall)
    scene.add_light("point", name="lamp", power=50.0, position=(0.0, 1.0, -2.0))
    scene.set_camera(look_at((0, 0, 0), (0, 5, 0)), 24, 24, fov=0.5)
    parts = render(scene).component_passes()
    top, bottom = (slice(2, 8), slice(4, 20)), (slice(16, 22), slice(4, 20))
    np.testing.assert_allclose(parts["GlossCol"], 0.9, rtol=1e-6)
    assert not parts["DiffCol"].any() and not parts["DiffDir"].any() and not parts["DiffInd"].any()
    np.testing.assert_allclose(parts["GlossDir"][top], np.broadcast_to(0.9 * GLOW, parts["GlossDir"][top].shape),
                               rtol=1e-5)
    assert parts["GlossInd"][bottom].min() > 0.0 and not parts["GlossDir"][bottom].any()


def test_glass_files_what_it_shows_as_transmission_and_caustics_lie_under_it():
    """The caustic Cornell box: seen through the glass ball, light is transmission light; on the floor
    under the ball, most of the indirect light is the caustic."""
    parts = render(core_scenes.cornell_3spheres(64, 48), passes=8).component_passes()
    trans = parts["TransInd"].sum(-1) + parts["TransDir"].sum(-1)
    through_glass = trans > 0.0
    assert through_glass.sum() > 20
    assert not parts["DiffDir"].sum(-1)[through_glass & (parts["DiffCol"].sum(-1) == 0)].any()
    caustic_share = parts["Caustic"].sum() / parts["DiffInd"].sum()
    brightest = np.unravel_index(np.argmax(parts["Caustic"].sum(-1)), trans.shape)
    assert 0.0 < caustic_share < 0.5
    assert parts["Caustic"][brightest].sum() > 0.5 * parts["DiffInd"][brightest].sum()


def test_a_diffuse_scene_has_no_caustic_and_no_glossy_light():
    parts = render(core_scenes.cornell_diffuse(48, 36)).component_passes()
    for name in ["Caustic", "GlossDir", "GlossInd", "TransDir", "TransInd", "GlossCol", "TransCol"]:
        assert not parts[name].any(), name
    assert parts["DiffDir"].max() > 0.0 and parts["DiffInd"].max() > 0.0


def test_component_passes_must_be_asked_for_and_need_what_they_read():
    renderer = ppm_core.Renderer(core_scenes.cornell_diffuse(16, 12), photons_per_pass=1000)
    renderer.run(passes=1)
    with pytest.raises(RuntimeError, match="component_passes=True"):
        renderer.component_passes()
    streamed = render(core_scenes.cornell_diffuse(16, 12), passes=1, hit_point_storage="streamed")
    with pytest.raises(RuntimeError, match="streamed"):
        streamed.component_passes()
    with pytest.raises(ValueError, match="direct_light"):
        ppm_core.Renderer(core_scenes.cornell_diffuse(16, 12), component_passes=True, direct_light="photons")
