"""Every light kind against an analytic answer, in both direct-light modes.

A diffuse plane (albedo rho) seen from straight above by an orthographic
camera; the radiance of a plane point is rho E / pi for irradiance E.
"""

import math

import numpy as np
import pytest

import ppm_core
from core_scenes import cornell_3spheres

pytestmark = pytest.mark.accuracy

RHO = 0.5


def plane_scene(width=16, height=16, extent=2.0):
    scene = ppm_core.Scene()
    mat = scene.add_material("plane", "diffuse", base_color=(RHO, RHO, RHO))
    # Small enough that the photons land near the camera's view; the top of a
    # plane sees the whole upper hemisphere whatever its size.
    c = np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], dtype=float)
    scene.add_mesh("plane", c, np.array([[0, 1, 2], [0, 2, 3]]), materials=mat)
    camera = np.eye(4)
    camera[2, 3] = 0.5
    scene.set_camera(camera, width, height, projection="orthographic", ortho_scale=extent, clip_start=0.0)
    return scene


def render(scene, passes, **settings):
    r = ppm_core.Renderer(scene, threads=2, **settings)
    r.run(passes=passes)
    return r.image()[..., 0]


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 1, 1e-6), ("photons", 40, 0.03)])
def test_sun(mode, passes, tol):
    scene = plane_scene()
    elevation = math.radians(60)
    direction = (0.0, -math.cos(elevation), -math.sin(elevation))
    scene.add_light("sun", power=3.0, direction=direction)
    image = render(scene, passes, direct_light=mode, photons_per_pass=50_000, initial_radius=0.3)
    expected = RHO * 3.0 * math.sin(elevation) / math.pi
    assert image.mean() == pytest.approx(expected, rel=tol)


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 60, 0.01), ("photons", 40, 0.03)])
def test_soft_sun(mode, passes, tol):
    scene = plane_scene()
    scene.add_light("sun", power=3.0, direction=(0, 0, -1), angle=math.radians(10))
    image = render(scene, passes, direct_light=mode, photons_per_pass=50_000, initial_radius=0.3)
    assert image.mean() == pytest.approx(RHO * 3.0 / math.pi, rel=tol)


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 40, 0.01), ("photons", 40, 0.03)])
def test_background(mode, passes, tol):
    scene = plane_scene()
    scene.set_background((0.2, 0.2, 0.2))
    image = render(scene, passes, direct_light=mode, photons_per_pass=50_000, initial_radius=0.3,
                   samples_per_pixel=16)
    assert image.mean() == pytest.approx(RHO * 0.2, rel=tol)


def disk_irradiance(radiance, a, h):
    return math.pi * radiance * a * a / (h * h + a * a)


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 60, 0.01), ("photons", 60, 0.03)])
def test_disk_and_rectangle_lights_on_axis(mode, passes, tol):
    # Small view of the plane right under the light, where E is nearly constant.
    for kind in ("disk", "rectangle"):
        scene = plane_scene(8, 8, extent=0.02)
        scene.add_light(kind, power=10.0, position=(0, 0, 1.0), direction=(0, 0, -1), size=0.5)
        image = render(scene, passes, direct_light=mode, photons_per_pass=100_000, initial_radius=0.05)
        area = math.pi * 0.25**2 if kind == "disk" else 0.25
        L = 10.0 / (math.pi * area)
        if kind == "disk":
            expected_e = disk_irradiance(L, 0.25, 1.0)
        else:  # square of side 2b on-axis at height h (Lambert's formula)
            b, h = 0.25, 1.0
            t = b / math.sqrt(b * b + h * h)
            expected_e = 4 * L * t * math.atan(b / math.sqrt(b * b + h * h))
        assert image.mean() == pytest.approx(RHO * expected_e / math.pi, rel=tol), kind


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 60, 0.01), ("photons", 60, 0.03)])
def test_a_spread_narrows_an_area_light_and_keeps_its_power(mode, passes, tol):
    """A small disk 1 m above the plane, of spread 2h: the radiance leaving at angle a is Lambertian
    times Cycles' soft-box factor (tan h - tan a) / (tan h - h), whose mean over the emitted
    directions is 1 (the power is kept, and photons carry it); outside the spread, nothing."""
    h = math.radians(60)
    scene = plane_scene(8, 8, extent=0.02)
    scene.add_light("disk", power=10.0, position=(0, 0, 1.0), direction=(0, 0, -1), size=0.01, spread=2 * h)
    image = render(scene, passes, direct_light=mode, photons_per_pass=100_000, initial_radius=0.05)
    x = (np.arange(8) + 0.5) / 8 * 0.02 - 0.01
    tan_a = np.hypot(*np.meshgrid(x, x))  # the pixels' distance from the axis, at 1 m
    irradiance = 10.0 / math.pi * (math.tan(h) - tan_a) / (math.tan(h) - h) / (1 + tan_a**2) ** 2  # L A f cos^4
    assert image.mean() == pytest.approx(RHO * irradiance.mean() / math.pi, rel=tol)
    aside = plane_scene(8, 8, extent=0.02)  # the plane's centre seen 63 degrees off the axis
    aside.add_light("disk", power=10.0, position=(2.0, 0, 1.0), direction=(0, 0, -1), size=0.01, spread=2 * h)
    assert render(aside, 2, direct_light=mode, photons_per_pass=20_000, initial_radius=0.05).max() == 0.0


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 1, 1e-6), ("photons", 60, 0.04)])
def test_spot_inside_and_outside_the_cone(mode, passes, tol):
    scene = plane_scene(16, 16, extent=4.0)
    # 60-degree cone pointing down from h = 1: the cone's edge is at r = tan(30 deg) = 0.577.
    scene.add_light("spot", power=100.0, position=(0, 0, 1.0), direction=(0, 0, -1),
                    spot_angle=math.radians(60), spot_blend=0.0)
    image = render(scene, passes, direct_light=mode, photons_per_pass=100_000, initial_radius=0.03)
    centre = image[7:9, 7:9].mean()  # pixels within 0.25 of the axis
    x = (np.arange(16) + 0.5) / 16 * 4.0 - 2.0
    X, Y = np.meshgrid(x, x)
    point_law = RHO / math.pi * 100.0 / (4 * math.pi) / (X**2 + Y**2 + 1.0) ** 1.5
    assert centre == pytest.approx(point_law[7:9, 7:9].mean(), rel=max(tol, 0.02))
    assert image[0, 0] == 0.0 and image[-1, -1] == 0.0  # corners are outside the cone


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 40, 0.01), ("photons", 60, 0.03)])
def test_sphere_light_matches_point_light_from_afar(mode, passes, tol):
    # A sphere light of radius a at height h gives E = I cos / d^2 exactly
    # (outside the sphere it radiates like a point source of the same intensity).
    scene = plane_scene(8, 8, extent=0.02)
    scene.add_light("point", power=100.0, position=(0, 0, 1.0), radius=0.3)
    image = render(scene, passes, direct_light=mode, photons_per_pass=100_000, initial_radius=0.05)
    assert image.mean() == pytest.approx(RHO / math.pi * 100.0 / (4 * math.pi), rel=tol)


@pytest.mark.parametrize("mode,passes,tol", [("sampled", 40, 0.01), ("photons", 60, 0.03)])
def test_spot_with_a_radius_is_a_sphere_light_inside_its_cone(mode, passes, tol):
    """On the axis, far inside a wide cone, a spot of radius a gives what the sphere light gives;
    outside the cone, nothing (the radius softens the edge only by its own angular size)."""
    scene = plane_scene(8, 8, extent=0.02)
    scene.add_light("spot", power=100.0, position=(0, 0, 1.0), direction=(0, 0, -1), radius=0.1,
                    spot_angle=math.radians(120), spot_blend=0.0)
    image = render(scene, passes, direct_light=mode, photons_per_pass=100_000, initial_radius=0.05)
    assert image.mean() == pytest.approx(RHO / math.pi * 100.0 / (4 * math.pi), rel=tol)
    outside = plane_scene(8, 8, extent=0.02)
    outside.add_light("spot", power=100.0, position=(3.0, 0, 0.5), direction=(1, 0, 0), radius=0.1,
                      spot_angle=math.radians(60), spot_blend=0.0)
    assert render(outside, 2, direct_light=mode, photons_per_pass=20_000, initial_radius=0.05).max() == 0.0


@pytest.mark.parametrize("kind", ["point", "spot"])
def test_soft_falloff_is_the_disk_facing_the_receiver_in_both_modes(kind):
    """Cycles' soft falloff (Blender's default for point and spot lights with a radius): a receiver
    sees the sphere as a disk of its radius r facing it, so a plane d below it gets E = I / (d^2 +
    r^2) on the axis, not the sphere's I / d^2 (light sampling, exact there). Photons from the sphere
    reach their first point only through that disk (soft_falloff_reaches): over a patch below it
    they agree with light sampling within 2% (with the whole sphere's photons they read (d^2 + r^2)
    / d^2 = 1.17 times as bright)."""
    def lit_plane(extent, mode, passes):
        scene = plane_scene(16, 16, extent=extent)
        scene.add_light(kind, power=100.0, position=(0, 0, 1.2), direction=(0, 0, -1), radius=0.5, soft_falloff=True,
                        spot_angle=math.radians(170), spot_blend=0.0)
        return render(scene, passes, direct_light=mode, photons_per_pass=200_000, initial_radius=0.05).mean()

    on_axis = lit_plane(0.02, "sampled", 40)
    assert on_axis == pytest.approx(RHO / math.pi * 100.0 / (4 * math.pi) / (1.2**2 + 0.5**2), rel=0.01)
    assert lit_plane(0.4, "photons", 40) == pytest.approx(lit_plane(0.4, "sampled", 20), rel=0.02)


def icosphere(subdivisions=3):
    t = (1 + 5**0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        cache, nf = {}, []

        def mid(a, b, cache=cache):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                cache[key] = len(verts) - 1
            return cache[key]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return np.array(verts), np.array(f)


@pytest.mark.parametrize("mode", ["sampled", "photons"])
def test_glowing_closed_room_is_emission_over_one_minus_albedo(mode):
    # Inside a closed room whose walls emit Le and reflect rho, L = Le / (1 - rho) everywhere.
    verts, faces = icosphere(2)
    scene = ppm_core.Scene()
    wall = scene.add_material("glow", "diffuse", base_color=(RHO,) * 3, emission=(0.3, 0.3, 0.3))
    scene.add_mesh("room", verts, faces, materials=wall)
    camera = np.eye(4)
    scene.set_camera(camera, 16, 16, fov=math.radians(60))
    image = render(scene, 60, direct_light=mode, photons_per_pass=50_000, max_bounces=40)
    assert image.mean() == pytest.approx(0.3 / (1 - RHO), rel=0.02)


def lit_cornell(lamp_position, background=(0.0, 0.0, 0.0), glow=(4.0, 3.0, 2.0), glow_color=(0.5, 0.5, 0.5)):
    """The Cornell box of core_scenes without its lamp, plus a quad under the ceiling glowing `glow`
    (its material the scene's last), one sphere lamp at `lamp_position` and a constant world."""
    scene = cornell_3spheres(24, 18)
    scene.remove_lights()
    glow = scene.add_material("glow", "diffuse", base_color=glow_color, emission=glow)
    quad = np.array([[-0.2, -0.2, 1.9], [0.2, -0.2, 1.9], [0.2, 0.2, 1.9], [-0.2, 0.2, 1.9]], dtype=float)
    scene.add_mesh("glow", quad, np.array([[0, 2, 1], [0, 3, 2]]), materials=glow)
    scene.add_light("sphere", name="lamp", power=25.0, position=lamp_position, radius=0.05)
    scene.set_background(background)
    return scene


@pytest.mark.parametrize("hit_points", ["fixed", "stochastic"])
def test_lights_replaced_after_a_build_render_as_a_scene_built_with_them(hit_points):
    # The viewport moves a lamp by replacing a built scene's lights (its BVH is kept): the image must
    # be the one of a scene exported afresh, emissive surfaces and world included.
    settings = {"photons_per_pass": 5_000, "threads": 2, "seed": 3, "hit_points": hit_points}
    edited = lit_cornell((0.0, 0.0, 1.3))
    ppm_core.Renderer(edited, **settings).run(passes=1)  # built, with the first lamp
    edited.remove_lights()
    edited.add_light("sphere", name="lamp", power=25.0, position=(0.4, 0.3, 1.0), radius=0.05)
    edited.set_background((0.05, 0.05, 0.1))
    fresh = lit_cornell((0.4, 0.3, 1.0), background=(0.05, 0.05, 0.1))
    edited_image, fresh_image, before = images_of([edited, fresh, lit_cornell((0.0, 0.0, 1.3))], settings)
    np.testing.assert_array_equal(edited_image, fresh_image)
    assert not np.array_equal(before, edited_image)  # the edit did change the image


def images_of(scenes, settings, passes=3):
    """Each scene's image after `passes` passes with `settings`."""
    images = []
    for scene in scenes:
        renderer = ppm_core.Renderer(scene, **settings)
        renderer.run(passes=passes)
        images.append(renderer.image())
    return images


def test_removing_the_lights_keeps_the_emissive_surfaces():
    scene = lit_cornell((0.0, 0.0, 1.3))
    scene.remove_lights()
    renderer = ppm_core.Renderer(scene, photons_per_pass=2_000, threads=2)
    renderer.run(passes=1)
    assert renderer.image()[..., :3].mean() > 0.0
    held = ppm_core.Renderer(scene, photons_per_pass=2_000, threads=2)
    with pytest.raises(RuntimeError):
        scene.remove_lights()  # a renderer holds the scene: the builders refuse to change it
    del held


def test_a_material_replaced_after_a_build_renders_as_a_scene_built_with_it():
    # The viewport's material edit: the material's slot gets the new values, the BVH is kept, and
    # what its emission lights is prepared again.
    settings = {"photons_per_pass": 5_000, "threads": 2, "seed": 5, "hit_points": "stochastic"}
    edited = lit_cornell((0.0, 0.0, 1.3))
    ppm_core.Renderer(edited, **settings).run(passes=1)
    glow = edited.add_material("probe") - 1  # the glow, the material before it
    assert edited.add_material("glow", "diffuse", base_color=(0.2, 0.6, 0.2), emission=(1.0, 6.0, 1.0),
                               replace=glow) == glow
    fresh = lit_cornell((0.0, 0.0, 1.3), glow=(1.0, 6.0, 1.0), glow_color=(0.2, 0.6, 0.2))
    edited_image, fresh_image, before = images_of([edited, fresh, lit_cornell((0.0, 0.0, 1.3))], settings)
    np.testing.assert_array_equal(edited_image, fresh_image)
    assert not np.array_equal(before, edited_image)
    with pytest.raises(ValueError, match="out of range"):
        edited.add_material("glow", replace=99)


def test_a_material_that_spheres_use_cannot_become_emissive():
    scene = ppm_core.Scene()
    matte = scene.add_material("matte")
    scene.add_sphere("ball", (0.0, 0.0, 0.0), 1.0, matte, 0)
    with pytest.raises(ValueError, match="spheres cannot emit"):
        scene.add_material("matte", emission=(1.0, 1.0, 1.0), replace=matte)
    scene.add_material("matte", base_color=(0.1, 0.2, 0.3), replace=matte)  # a colour edit is fine
