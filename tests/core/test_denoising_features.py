"""Cycles' Denoising Albedo and Denoising Normal from the core (Renderer.denoising_features,
engine/ppm/denoising_features.h): the features of the first surface an eye path does not follow,
through the tint of the mirrors and glass it does follow; nothing where it sees only the sky. The
agreement with Cycles' own passes is tests/cli/denoising_compare.py's."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core
from core_scenes import look_at, quad

FLOOR = (0.2, 0.6, 0.3)


def scene_over_floor(camera, fov_degrees, width=32, height=24):
    scene = ppm_core.Scene()
    floor = scene.add_material("floor", "diffuse", base_color=FLOOR)
    quad(scene, "floor", [(-50, -50, 0), (50, -50, 0), (50, 50, 0), (-50, 50, 0)], floor)
    scene.add_light("point", name="lamp", power=100.0, position=(0.0, 0.0, 4.0))
    scene.set_camera(camera, width, height, fov=math.radians(fov_degrees))
    return scene


def features(scene, samples=4, **settings):
    return ppm_core.Renderer(scene, photons_per_pass=1000, **settings).denoising_features(samples)


def test_a_diffuse_floor_gives_its_colour_and_its_normal():
    f = features(scene_over_floor(look_at((0, -2, 3), (0, 0, 0)), 40))
    assert f["albedo"].shape == f["normal"].shape == (24, 32, 3)
    np.testing.assert_allclose(f["albedo"], np.broadcast_to(FLOOR, (24, 32, 3)), atol=1e-5)
    np.testing.assert_allclose(f["normal"], np.broadcast_to((0, 0, 1), (24, 32, 3)), atol=1e-5)


def test_the_sky_gives_nothing():
    f = features(scene_over_floor(look_at((0, 0, 3), (0, 5, 4)), 20))  # looking up, away from the floor
    assert not f["albedo"].any() and not f["normal"].any()


def test_a_mirror_is_seen_through_with_its_tint():
    """A 45-degree mirror fills the view and shows the floor below: albedo = mirror tint x floor."""
    scene = scene_over_floor(look_at((0, -5, 2), (0, 0, 2)), 8)
    tint = (0.9, 0.5, 0.7)
    mirror = scene.add_material("mirror", "mirror", base_color=tint)
    quad(scene, "mirror", [(-1, 0.5, 1.5), (1, 0.5, 1.5), (1, -0.5, 2.5), (-1, -0.5, 2.5)], mirror)
    f = features(scene)
    np.testing.assert_allclose(f["albedo"], np.broadcast_to(np.multiply(tint, FLOOR), (24, 32, 3)), atol=1e-4)
    np.testing.assert_allclose(f["normal"], np.broadcast_to((0, 0, 1), (24, 32, 3)), atol=1e-4)


@pytest.mark.parametrize("roughness, sees_the_floor", [(0.05, True), (0.4, False)])
def test_a_glossy_mirror_is_seen_through_only_while_cycles_counts_it_smooth(roughness, sees_the_floor):
    """Eye paths follow glossy lobes at every roughness; as Cycles, the features are the glossy
    surface's own (its colour, its normal) where it is rougher than 0.075, and what it reflects
    (the floor, tinted) where it is smoother."""
    scene = scene_over_floor(look_at((0, -5, 2), (0, 0, 2)), 8)
    tint = (0.9, 0.5, 0.7)
    mirror = scene.add_material("mirror", "mixture", lobes=[{"kind": "glossy", "color": tint, "roughness": roughness}])
    quad(scene, "mirror", [(-1, 0.5, 1.5), (1, 0.5, 1.5), (1, -0.5, 2.5), (-1, -0.5, 2.5)], mirror)
    f = features(scene, samples=16)
    if sees_the_floor:  # (up to the share of the lobe's draws that leave the floor for the sky)
        assert np.median(f["albedo"] / np.multiply(tint, FLOOR)) == pytest.approx(1.0, abs=0.02)
        assert np.median(f["normal"][..., 2]) > 0.95
    else:
        np.testing.assert_allclose(f["albedo"], np.broadcast_to(tint, (24, 32, 3)), atol=1e-4)
        facing = np.array([0.0, -1.0, -1.0]) / math.sqrt(2.0)  # the mirror faces the camera and the floor
        np.testing.assert_allclose(f["normal"], np.broadcast_to(facing, (24, 32, 3)), atol=1e-4)


def test_a_glass_pane_passes_its_fresnel_transmission():
    """Seen straight down through a smooth glass pane (two interfaces at normal incidence) the floor's
    albedo is weighted by the light the pane lets through, about (1 - F)^2 with F = 0.04 at IOR 1.5;
    what the pane reflects goes to the sky and adds nothing."""
    scene = scene_over_floor(look_at((0, 0, 5), (0, 0, 0), up=(0, 1, 0)), 10)
    glass = scene.add_material("glass", "glass", base_color=(1, 1, 1), ior=1.5)
    top, bottom = 1.1, 1.0
    quad(scene, "pane_top", [(-5, -5, top), (5, -5, top), (5, 5, top), (-5, 5, top)], glass)
    quad(scene, "pane_bottom", [(-5, -5, bottom), (-5, 5, bottom), (5, 5, bottom), (5, -5, bottom)], glass)
    f = features(scene, samples=16)
    fresnel = ((1.5 - 1.0) / (1.5 + 1.0)) ** 2
    through = f["albedo"] / np.asarray(FLOOR)
    assert through.mean() == pytest.approx((1 - fresnel) ** 2, abs=0.01), through.mean()
    # As Cycles, whose path takes one branch: the floor's normal, times the chance of reaching the
    # floor (for clear glass the same share as its light); the branches to the sky add nothing.
    np.testing.assert_allclose(f["normal"][..., :2], 0.0, atol=1e-6)
    np.testing.assert_allclose(f["normal"][..., 2], through.mean(axis=-1), atol=1e-4)


def test_features_made_band_by_band_are_those_of_one_eye_pass():
    """Above 2^20 eye samples the features are made in bands of rows: the same as the whole image's
    rows (each band draws its rows' own random samples)."""
    scene = core_scenes.cornell_3spheres(256, 256)
    renderer = ppm_core.Renderer(scene, photons_per_pass=1000)
    banded = renderer.denoising_features(32)  # 2^21 samples: two bands
    small = ppm_core.Renderer(core_scenes.cornell_3spheres(256, 256), photons_per_pass=1000)
    whole = small.denoising_features(16)  # 2^20 samples: one band
    assert np.isfinite(banded["albedo"]).all() and banded["albedo"].max() > 0.5
    # 32 and 16 samples of the same pixels: their means agree but for anti-aliasing at edges.
    assert np.median(np.abs(banded["albedo"] - whole["albedo"])) < 1e-3
    assert np.abs(banded["albedo"][:128] - whole["albedo"][:128]).mean() < 0.02
    assert np.abs(banded["albedo"][128:] - whole["albedo"][128:]).mean() < 0.02


def test_bad_sample_counts_are_refused():
    renderer = ppm_core.Renderer(scene_over_floor(look_at((0, -2, 3), (0, 0, 0)), 40), photons_per_pass=1000)
    with pytest.raises(ValueError, match="samples_per_pixel"):
        renderer.denoising_features(-1)
    assert renderer.denoising_features(0)["albedo"].shape == (24, 32, 3)  # 0: the settings' samples
