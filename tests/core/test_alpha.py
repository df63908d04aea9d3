"""Alpha as Cycles makes it: a transparent film, glass over it (transparent glass off and on),
holdout objects and the holdout material; RGB premultiplied. And a sun's disc seen in a mirror."""

import math

import numpy as np
import pytest

import ppm_core

QUAD = np.array([[0, 1, 2], [0, 2, 3]])


def square(scene, name, half, z, material, **kwargs):
    corners = np.array([[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]], dtype=float)
    scene.add_mesh(name, corners, QUAD, materials=material, **kwargs)


def scene_over_sky(front=None, front_kind="diffuse", holdout=False):
    """Seen from above, looking down: a floor covering the left half of the view, nothing beyond the
    right half (the sky); `front`: the half-size of a square at z = 1 in the middle."""
    scene = ppm_core.Scene()
    grey = scene.add_material("grey", base_color=(0.5, 0.5, 0.5))
    left = np.array([[-2, -2, 0], [0, -2, 0], [0, 2, 0], [-2, 2, 0]], dtype=float)
    scene.add_mesh("floor", left, QUAD, materials=grey)
    if front is not None:
        material = scene.add_material("front", front_kind, base_color=(1.0, 1.0, 1.0))
        square(scene, "front", front, 1.0, material, holdout=holdout)
    scene.set_background((0.6, 0.6, 0.6))
    camera = np.eye(4)
    camera[2, 3] = 3.0
    scene.set_camera(camera, 16, 16, projection="orthographic", ortho_scale=2.0)
    return scene


def render(scene, **settings):
    renderer = ppm_core.Renderer(scene, **{"photons_per_pass": 2000, "samples_per_pixel": 4, "threads": 1,
                                           "seed": 2, **settings})
    renderer.run(passes=2)
    return renderer.image()


def test_a_transparent_film_leaves_the_sky_transparent_and_black():
    opaque = render(scene_over_sky())
    film = render(scene_over_sky(), transparent_background=True)
    sky, floor = (slice(None), slice(12, 16)), (slice(None), slice(0, 4))
    assert (opaque[..., 3] == 1.0).all()
    np.testing.assert_allclose(opaque[sky][..., :3], 0.6, rtol=1e-6)
    assert (film[sky][..., 3] == 0.0).all() and (film[sky][..., :3] == 0.0).all()
    assert (film[floor][..., 3] == 1.0).all()
    np.testing.assert_allclose(film[floor], opaque[floor], rtol=1e-6)


@pytest.mark.parametrize("transparent_background", [False, True])
def test_a_holdout_object_cuts_a_hole_whatever_the_film(transparent_background):
    image = render(scene_over_sky(front=0.5, holdout=True), transparent_background=transparent_background)
    hole = image[6:10, 6:10]
    assert (hole[..., 3] == 0.0).all() and (hole[..., :3] == 0.0).all()
    assert (image[0:2, 0:4, 3] == 1.0).all()


def test_a_holdout_object_is_itself_to_other_rays():
    """Its shadow on the floor stays (a holdout material would also cast one: the difference is in
    the light it reflects, checked against Cycles by tests/blenders/alpha_compare.py)."""
    scene = scene_over_sky(front=0.5, holdout=True)
    hits = scene.intersect(np.array([[0.0, 0.0, 3.0]]), np.array([[0.0, 0.0, -1.0]]), ray_kind="shadow")
    assert hits["t"][0] == pytest.approx(2.0)


def test_glass_over_a_transparent_film():
    """A smooth glass sheet (one surface) over the sky: opaque showing the sky behind it (Cycles'
    default), or, with transparent glass, transparent by what it transmits, its reflection kept as
    premultiplied colour."""
    scene = lambda: scene_over_sky(front=0.5, front_kind="glass")  # noqa: E731
    over_sky = (slice(6, 10), slice(10, 12))  # the pane's right part, over the sky
    shown = render(scene(), transparent_background=True)[over_sky]
    cut = render(scene(), transparent_background=True, transparent_glass=True)[over_sky]
    assert (shown[..., 3] == 1.0).all()
    transmitted = 1.0 - cut[..., 3].mean()
    reflectance = ((1.45 - 1) / (1.45 + 1)) ** 2  # at normal incidence
    assert transmitted == pytest.approx(1 - reflectance, rel=1e-3)
    assert 0.0 < cut[..., :3].mean() < 0.2 * shown[..., :3].mean()  # what it reflects, not the sky behind


def test_a_sun_disc_shows_in_a_mirror_unless_hidden_from_glossy_rays():
    def mirror_under_sun(visibility):
        scene = ppm_core.Scene()
        mirror = scene.add_material("mirror", "mirror", base_color=(0.8, 0.8, 0.8))
        square(scene, "floor", 4.0, 0.0, mirror)
        scene.add_light("sun", power=3.0, direction=(0.0, 0.0, -1.0), angle=math.radians(20), visibility=visibility)
        camera = np.eye(4)
        camera[2, 3] = 3.0
        scene.set_camera(camera, 8, 8, projection="orthographic", ortho_scale=2.0)
        return render(scene)[..., :3]
    sun_radiance = 3.0 / (math.pi * math.sin(math.radians(10)) ** 2)
    np.testing.assert_allclose(mirror_under_sun(None), 0.8 * sun_radiance, rtol=1e-6)
    assert mirror_under_sun(["camera", "diffuse", "transmission", "shadow"]).max() == 0.0


def mixture_over_sky(lobes, holdout=0.0):
    """scene_over_sky with its front square a mixture."""
    scene = scene_over_sky()
    material = scene.add_material("front", "mixture", lobes=lobes, holdout=holdout)
    square(scene, "front", 0.5, 1.0, material)
    return scene


def test_a_mixtures_holdout_cuts_its_share_of_the_alpha():
    over_sky = (slice(6, 10), slice(10, 12))  # the square's right part, over the sky
    lobes = [{"kind": "diffuse", "weight": 0.75, "color": 1.0}]
    image = render(mixture_over_sky(lobes, holdout=0.25))[over_sky]
    np.testing.assert_allclose(image[..., 3], 0.75, atol=1e-6)  # whatever the film: camera rays cut it
    opaque = render(mixture_over_sky(lobes))[over_sky]
    np.testing.assert_allclose(image[..., :3], opaque[..., :3], rtol=1e-6)  # the rest shades the same


def test_the_sky_through_a_transparent_lobe_stays_transparent_in_the_film():
    over_sky = (slice(6, 10), slice(10, 12))
    half = [{"kind": "transparent", "weight": 0.5, "color": 1.0}, {"kind": "diffuse", "weight": 0.5, "color": 1.0}]
    # The eye pass picks one lobe per sample: 512 samples leave the mean 0.022 from 0.5 (one sigma).
    image = render(mixture_over_sky(half), transparent_background=True, samples_per_pixel=64)[over_sky]
    np.testing.assert_allclose(image[..., 3].mean(), 0.5, atol=0.08)
    clear = [{"kind": "transparent", "weight": 1.0, "color": 1.0}]
    image = render(mixture_over_sky(clear), transparent_background=True)[over_sky]
    assert (image[..., 3] == 0.0).all()


def test_holdout_belongs_to_mixtures_in_range():
    with pytest.raises(ValueError, match="mixture"):
        ppm_core.Scene().add_material("m", "diffuse", holdout=0.5)
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        ppm_core.Scene().add_material("m", "mixture", lobes=[{"kind": "diffuse"}], holdout=1.5)
