"""Depth of field (POST and LENS) and stochastic PPM.

An emissive plane split into a bright and a dark half is seen head-on; its edge
is sharp at the focus distance S, and at 2S it is blurred by a disk whose
diameter the thin-lens equation predicts: c = 2 R |1/S - 1/z| / pixel_angle.
"""

import math

import numpy as np
import pytest

import ppm_core

W, H = 128, 32
FOV = math.radians(40)
PIXEL = 2 * math.tan(FOV / 2) / W  # footprint at unit distance
S = 2.0


def edge_scene(depth, aperture_radius):
    scene = ppm_core.Scene()
    bright = scene.add_material("bright", "emission", emission=(1.0, 1.0, 1.0))
    dark = scene.add_material("dark", "emission", emission=(0.0, 0.0, 0.0))
    half = depth  # wide enough to fill the view and the blur margin
    z = -depth
    left = np.array([[-half, -half, z], [0, -half, z], [0, half, z], [-half, half, z]])
    right = np.array([[0, -half, z], [half, -half, z], [half, half, z], [0, half, z]])
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    scene.add_mesh("bright", left, tris, materials=bright)
    scene.add_mesh("dark", right, tris, materials=dark)
    scene.set_camera(np.eye(4), W, H, fov=FOV, focus_distance=S, aperture_radius=aperture_radius)
    return scene


def edge_profile(mode, depth, aperture_radius, **settings):
    scene = edge_scene(depth, aperture_radius)
    extra = dict(hit_points="stochastic", samples_per_pixel=1) if mode == "lens" else dict(samples_per_pixel=16)
    extra.update(settings)
    r = ppm_core.Renderer(scene, photons_per_pass=1, threads=2, dof_mode=mode, **extra)
    r.run(passes=400 if mode == "lens" else 1)
    return r.image()[..., 0].mean(axis=0), r.stats()


def width_10_90(profile):
    """Distance in pixels over which a falling edge goes from 90% to 10%."""
    hi, lo = profile[:8].mean(), profile[-8:].mean()
    p = (profile - lo) / (hi - lo)
    x = np.arange(len(p)) + 0.5

    def crossing(level):
        i = np.nonzero(p < level)[0][0]
        return x[i - 1] + (p[i - 1] - level) / (p[i - 1] - p[i])

    return crossing(0.1) - crossing(0.9)


def disk_edge_width(diameter):
    """10-90% width of a step blurred by a uniform disk of this diameter (pixels)."""
    r = diameter / 2

    def covered(x):  # fraction of the disk left of a line at distance x from its centre
        x = np.clip(x / r, -1, 1)
        return 1 - (np.arccos(x) - x * np.sqrt(1 - x * x)) / math.pi

    xs = np.linspace(-r, r, 20001)
    f = covered(xs)
    return xs[np.searchsorted(f, 0.9)] - xs[np.searchsorted(f, 0.1)]


APERTURE = 16 * PIXEL * S  # CoC of 16 pixels at 2S


@pytest.mark.parametrize("mode", ["post", "lens"])
def test_in_focus_edge_stays_sharp(mode):
    profile, _ = edge_profile(mode, S, APERTURE)
    assert width_10_90(profile) < 1.0


@pytest.mark.parametrize("mode", ["post", "lens"])
def test_edge_at_twice_focus_blurs_by_predicted_coc(mode):
    coc = 2 * APERTURE * abs(1 / S - 1 / (2 * S)) / PIXEL
    assert coc == pytest.approx(16.0)
    profile, _ = edge_profile(mode, 2 * S, APERTURE)
    assert width_10_90(profile) == pytest.approx(disk_edge_width(coc), rel=0.10)


def test_dof_work_is_skipped_when_it_cannot_show():
    _, stats = edge_profile("post", 2 * S, 1e-6)  # CoC far under a pixel
    assert any("circle of confusion under a pixel" in s for s in stats["skipped"])
    _, stats = edge_profile("off", 2 * S, APERTURE)
    assert any("depth of field: off" in s for s in stats["skipped"])


