"""Emitting media light the scene (scene/medium_lights.cpp, ppm/photon_tracer_media.h): a closed mesh
whose material carries a medium with emission L_e emits 4 pi L_e V watts in photons, which deposit
from their first hit (no light sampling reaches a medium), while the eye keeps seeing the emission
itself along its rays.

- an absorbing, emitting box lights a floor beside it: each pixel against the irradiance integrated
  here with numpy, E = int L_e (1 - exp(-sigma_a l(w))) / sigma_a cos dw (l: the chord through the box);
- energy: a scattering, non-absorbing octahedron in a closed box of grey walls: the walls absorb
  all it emits, so the flux arriving on them is P / (1 - albedo), a sixth of it on each wall;
- a furnace: a medium with L_e = sigma_a (radiance L_e / sigma_a = 1 at equilibrium) in an enclosure
  of walls of radiance 1 that reflect nothing is 1 everywhere, whatever it scatters: the emission
  seen directly, the walls' light and the medium's own light scattered in must add up to exactly 1,
  so a missing or doubled part shows;
- what emits no photons (the world's medium, open and flat meshes) is named in stats()["skipped"];
  huge regions render finite.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_media import box, render

import ppm_core
from core_scenes import look_at, quad


def chord(origin, directions, lo, hi):
    """The length of each ray from `origin` along `directions` inside the box [lo, hi]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (lo[None] - origin[None]) / directions
        t2 = (hi[None] - origin[None]) / directions
    near = np.nanmax(np.minimum(t1, t2), axis=1)
    far = np.nanmin(np.maximum(t1, t2), axis=1)
    return np.maximum(0.0, far - np.maximum(near, 0.0))


def box_irradiance(point, lo, hi, emission, sigma_a, n=300):
    """Irradiance on an upward-facing point from an emitting, absorbing box, per channel: a midpoint
    rule over (cos theta, phi) of the radiance leaving the box, L_e (1 - exp(-sigma_a l)) / sigma_a."""
    mu = (np.arange(n) + 0.5) / n
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * math.pi
    m, f = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m**2)
    d = np.stack([s * np.cos(f), s * np.sin(f), m], -1).reshape(-1, 3)
    length = chord(np.asarray(point, float), d, np.asarray(lo, float), np.asarray(hi, float))
    weight = m.reshape(-1) * (1.0 / n) * (math.pi / n)  # cos dmu dphi
    return np.array([np.sum(e * -np.expm1(-a * length) / a * weight) for e, a in zip(emission, sigma_a)])


def glowing_material(scene, name, **medium):
    scene.add_medium(name, **medium)
    return scene.add_material(name, "diffuse", medium=name, surface=False)


@pytest.mark.accuracy
def test_an_emitting_absorbing_box_lights_a_floor_as_integrated():
    """A box of 1 x 1 x 0.5 m, emission 1 per metre, sigma_a (0.5, 2, 8), 0.5 m above a floor of
    albedo 0.8: the floor beside it (x 0.9-1.5 m, seen from below the box) has radiance 0.8 E / pi,
    all of it from the medium's photons' first hits (direct light is sampled, and nothing samples
    the medium). Measured: the mean 1.002-1.003 of the integral per channel, 2x2 blocks 0.979-1.025.
    Without those deposits the floor is black; a power off by any factor shows."""
    lo, hi = np.array([-0.5, -0.5, 0.5]), np.array([0.5, 0.5, 1.0])
    sigma_a = (0.5, 2.0, 8.0)
    scene = ppm_core.Scene()
    glow = glowing_material(scene, "glow", sigma_a=sigma_a, emission=1.0)
    floor = scene.add_material("floor", "diffuse", base_color=0.8)
    box(scene, "glow", lo, hi, glow, 0)
    quad(scene, "floor", [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], floor, object_id=1)
    scene.set_camera(look_at((1.2, 0.0, 0.3), (1.2, 0.0, 0.0), up=(0, 1, 0)), 8, 8, fov=1.6)
    origins, directions = scene.camera_rays()
    points = origins - directions * (origins[:, 2] / directions[:, 2])[:, None]  # on the floor, bottom row first
    expected = np.array([0.8 / math.pi * box_irradiance(p, lo, hi, (1.0,) * 3, sigma_a) for p in points])
    expected = expected.reshape(8, 8, 3)[::-1]  # the image's rows run top-down
    image, _ = render(scene, passes=40, photons_per_pass=100_000, initial_radius=0.06)
    np.testing.assert_allclose(image.mean(axis=(0, 1)), expected.mean(axis=(0, 1)), rtol=0.03)
    blocks = lambda a: a.reshape(2, 4, 2, 4, 3).mean(axis=(1, 3))  # noqa: E731
    np.testing.assert_allclose(blocks(image), blocks(expected), rtol=0.06)


def octahedron(scene, name, radius, material, object_id):
    """A regular octahedron about the origin, corners on the axes at `radius`, faces outward:
    volume 4/3 radius^3, a sixth of its bounding box (so its points are drawn by rejection)."""
    corners = radius * np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    tris = []
    for x in (0, 1):
        for y in (2, 3):
            for z in (4, 5):
                t = [x, y, z]
                if np.dot(np.cross(corners[y] - corners[x], corners[z] - corners[x]), corners[x]) < 0:
                    t = [x, z, y]
                tris.append(t)
    scene.add_mesh(name, corners, np.array(tris), materials=material, object_id=object_id)


@pytest.mark.accuracy
def test_a_closed_box_of_grey_walls_receives_the_medium_s_power():
    """An octahedron (radius 0.5 m, V = 1/6 m^3) of non-absorbing, scattering medium emitting
    (1, 0.5, 0.25) per metre, in a closed 2 m box of walls of albedo 0.5: every watt emitted ends
    absorbed by the walls, which absorb half of what arrives, so P / (1 - 0.5) arrives, P = 4 pi L_e
    V, a sixth on each wall by symmetry. An orthographic camera between the medium and the ceiling
    sees the whole ceiling: its mean radiance is 0.5 E / pi, E = P / (0.5 * 6 * 4 m^2): measured
    1.010-1.012 of it per channel (the gather at the ceiling's edges and corners). Without the
    first hits' deposits 0.5 of it would arrive; with a volume or power off, a factor."""
    emission = np.array([1.0, 0.5, 0.25])
    scene = ppm_core.Scene()
    glow = glowing_material(scene, "glow", sigma_s=(2.0, 1.0, 0.5), emission=tuple(emission))
    wall = scene.add_material("wall", "diffuse", base_color=0.5)
    box(scene, "walls", (-1, -1, -1), (1, 1, 1), wall, 0, inward=True)
    octahedron(scene, "glow", 0.5, glow, 1)
    scene.set_camera(look_at((0, 0, 0.9), (0, 0, 1.0), up=(0, 1, 0)), 24, 24, projection="orthographic",
                     ortho_scale=2.0)
    image, r = render(scene, passes=30, photons_per_pass=50_000, initial_radius=0.02, max_bounces=1000)
    power = 4 * math.pi * emission * (4 / 3 * 0.5**3)
    expected = 0.5 / math.pi * power / (0.5 * 6 * 4.0)
    np.testing.assert_allclose(image.mean(axis=(0, 1)), expected, rtol=0.03)
    assert not any("photons from" in s for s in r.stats()["skipped"])


@pytest.mark.accuracy
@pytest.mark.parametrize("direct", ["sampled", "photons"])
def test_an_emitting_furnace_is_uniform(direct):
    """Walls of radiance 1 that reflect nothing around a 1.6 m box of medium with emission equal to
    its absorption (0.5, 1, 0.25) and scattering (1, 0.5, 1): radiance L_e / sigma_a = 1 is the
    equilibrium, so the camera sees 1 through the medium wherever it looks. The eye adds the
    medium's emission along its rays, the walls' light arrives by light sampling (or photons) and
    photons, the medium's own light scattered in by its photons alone. Measured over seeds 3-5, both
    ways: means 0.971-1.000, the centre 0.964-0.999 (the 3-D estimate's boundary bias and noise);
    without the medium's photons (the core before them) 0.74-0.83, and counted twice they would add
    as much again."""
    sigma_a = (0.5, 1.0, 0.25)
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", "emission", emission=(1.0, 1.0, 1.0))
    glow = glowing_material(scene, "glow", sigma_a=sigma_a, sigma_s=(1.0, 0.5, 1.0), emission=sigma_a)
    box(scene, "enclosure", (-1, -1, -1), (1, 1, 1), wall, 0, inward=True)
    box(scene, "glow", (-0.8, -0.8, -0.8), (0.8, 0.8, 0.8), glow, 1)
    scene.set_camera(look_at((0, -0.95, 0), (0, 0, 0)), 12, 12, fov=0.9)
    image, _ = render(scene, passes=60, photons_per_pass=40_000, initial_radius=0.08, max_bounces=1000,
                      direct_light=direct)
    assert np.all(np.isfinite(image))
    np.testing.assert_allclose(image.mean(axis=(0, 1)), 1.0, rtol=0.04)
    np.testing.assert_allclose(image[3:9, 3:9].mean(axis=(0, 1)), 1.0, rtol=0.06)


@pytest.mark.accuracy
def test_a_glowing_box_in_a_fog_box_lights_through_the_fog():
    """A glowing box inside a fog box (absorbing, 0.4 per metre) that holds the floor and the camera,
    against the same fog as the World's medium: the glow's photons start in the fog around the box
    too, so the floor reads the same (every 4x4 block within 4%). Starting in the box's own medium
    alone, they crossed the fog box unattenuated once out of the glow: blocks up to 3.1 times as
    bright."""
    def scene_of(world_fog):
        scene = ppm_core.Scene()
        scene.add_medium("fog", sigma_a=(0.4, 0.4, 0.4))
        if world_fog:
            scene.set_world_medium("fog")
        else:
            fog = scene.add_material("fog", "diffuse", medium="fog", surface=False)
            box(scene, "fog", (-6, -6, -1), (6, 6, 5), fog, 2)
        glow = glowing_material(scene, "glow", sigma_a=(1.0, 1.0, 1.0), emission=(4.0, 3.0, 2.0))
        box(scene, "glow", (-0.5, -0.5, 1.0), (0.5, 0.5, 2.0), glow, 0)
        floor = scene.add_material("floor", "diffuse", base_color=(0.8, 0.8, 0.8))
        quad(scene, "floor", [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], floor, object_id=1)
        scene.set_camera(look_at((0, -4, 3), (0, 0, 0.5)), 16, 16, fov=0.9)
        image, _ = render(scene, passes=40, photons_per_pass=40_000)
        return image.mean(axis=2).reshape(4, 4, 4, 4).mean(axis=(1, 3))
    np.testing.assert_allclose(scene_of(False), scene_of(True), rtol=0.04)


def test_what_emits_no_photons_is_named_and_renders():
    """The world's emitting medium (unbounded power), an open mesh and a flat one emit no photons:
    each a line in stats()["skipped"]; the render is finite and still sees the world's emission."""
    scene = ppm_core.Scene()
    scene.add_medium("haze", sigma_a=0.1, emission=0.05)
    scene.set_world_medium("haze")
    glow = glowing_material(scene, "glow", sigma_a=0.5, emission=1.0)
    floor = scene.add_material("floor", "diffuse", base_color=0.5)
    quad(scene, "sheet", [[-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], glow, object_id=0)
    box(scene, "flat", (2, 2, 1), (3, 3, 1), glow, 1)
    quad(scene, "floor", [[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], floor, object_id=2)
    scene.add_light("point", power=50.0, position=(0, 0, 3))
    scene.set_camera(look_at((0, -3, 2), (0, 0, 0.5)), 8, 8)
    image, r = render(scene, passes=2, photons_per_pass=2000)
    skipped = r.stats()["skipped"]
    assert any("world medium" in s for s in skipped)
    assert any("in object 0: 4 open edges" in s for s in skipped)
    assert any("in object 1: no volume" in s for s in skipped)
    assert np.all(np.isfinite(image)) and image.min() > 0  # the haze glows along every ray


@pytest.mark.parametrize("size", [1e-30, 1e25])
def test_tiny_and_huge_emitting_boxes_render_finite(size):
    """A box of emitting, scattering medium 1e-30 m or 1e25 m across (power 4 pi L_e V from 1e-89 to
    1e76 W) above a floor the camera looks at: no NaN, no infinity."""
    scene = ppm_core.Scene()
    glow = glowing_material(scene, "glow", sigma_a=1e-3, sigma_s=1e-3, emission=1.0)
    floor = scene.add_material("floor", "diffuse", base_color=0.5)
    box(scene, "glow", (-size, -size, size), (size, size, 2 * size), glow, 0)
    quad(scene, "floor", [[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], floor, object_id=1)
    scene.set_camera(look_at((0, -3, 2), (0, 0, 0)), 8, 8)
    image, r = render(scene, passes=2, photons_per_pass=2000)
    assert np.all(np.isfinite(image))
    assert r.stats()["photons_deposited"] > 0
