"""Ray visibility as Cycles has it: each object and light names the kinds of ray that see it
(camera, diffuse, glossy, transmission, shadow), and a light may cast no shadow."""

import numpy as np
import pytest

import ppm_core

NOT_CAMERA = ["diffuse", "glossy", "transmission", "shadow"]
EVERY_KIND = ["camera"] + NOT_CAMERA


def square(scene, name, half, z, material, visibility=None):
    corners = np.array([[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]], dtype=float)
    scene.add_mesh(name, corners, np.array([[0, 1, 2], [0, 2, 3]]), materials=material, visibility=visibility)


def floor_scene(occluder=None, cast_shadow=True, floor_kind="diffuse"):
    """A floor lit by a point light at z = 2, seen from above; `occluder` is the visibility of a
    black square at z = 1 between them (None: no square)."""
    scene = ppm_core.Scene()
    floor = scene.add_material("floor", floor_kind, base_color=(0.5, 0.5, 0.5))
    black = scene.add_material("black", base_color=(0.0, 0.0, 0.0))
    square(scene, "floor", 4.0, 0.0, floor)
    if occluder is not None:
        square(scene, "occluder", 0.5, 1.0, black, occluder)
    scene.add_light("point", position=(0.0, 0.0, 2.0), power=200.0, cast_shadow=cast_shadow)
    camera = np.eye(4)
    camera[2, 3] = 3.0
    scene.set_camera(camera, 16, 16, projection="orthographic", ortho_scale=4.0)  # [-2, 2]: the shadow covers [-1, 1]
    return scene


def render(scene, passes=2):
    renderer = ppm_core.Renderer(scene, photons_per_pass=2000, samples_per_pixel=1, threads=1, seed=9)
    renderer.run(passes=passes)
    return renderer.image()[..., :3].mean(axis=2)


def centre(image):
    return image[6:10, 6:10].mean()


def test_an_object_hidden_from_the_camera_still_casts_its_shadow():
    lit = render(floor_scene())
    seen = render(floor_scene(occluder=EVERY_KIND))
    hidden = render(floor_scene(occluder=NOT_CAMERA))
    assert centre(lit) > 0.05
    assert centre(seen) == 0.0  # the black square itself
    assert centre(hidden) < 0.02 * centre(lit)  # the floor, in the square's shadow
    assert hidden[0, 0] == pytest.approx(lit[0, 0], rel=0.05)  # outside the shadow


def test_an_object_that_casts_no_shadow_lets_direct_light_through():
    lit = render(floor_scene())
    no_shadow = render(floor_scene(occluder=["diffuse", "glossy", "transmission"]))
    np.testing.assert_allclose(no_shadow, lit, rtol=1e-6)  # a black square adds no light either


def test_a_light_that_casts_no_shadow_lights_through_everything():
    lit = render(floor_scene())
    unshadowed = render(floor_scene(occluder=NOT_CAMERA, cast_shadow=False))
    assert centre(unshadowed) == pytest.approx(centre(lit), rel=1e-6)


def test_an_object_hidden_from_glossy_rays_is_not_in_a_mirror():
    """A mirror floor under a glowing square: the camera sees the square's reflection unless the
    square hides from glossy rays (it still hides the mirror from the camera if camera-visible)."""
    def mirror_image(visibility):
        scene = ppm_core.Scene()
        mirror = scene.add_material("mirror", "mirror", base_color=(0.9, 0.9, 0.9))
        glow = scene.add_material("glow", "emission", emission=(2.0, 2.0, 2.0))
        square(scene, "floor", 4.0, 0.0, mirror)
        corners = np.array([[-0.5, -0.5, 1], [-0.5, 0.5, 1], [0.5, 0.5, 1], [0.5, -0.5, 1]], dtype=float)
        scene.add_mesh("glow", corners, np.array([[0, 1, 2], [0, 2, 3]]), materials=glow, visibility=visibility)
        camera = np.eye(4)
        camera[2, 3] = 3.0
        scene.set_camera(camera, 16, 16, projection="orthographic", ortho_scale=2.0)
        return render(scene, passes=1)
    assert centre(mirror_image(NOT_CAMERA)) == pytest.approx(0.9 * 2.0, rel=1e-6)
    assert centre(mirror_image(["camera", "diffuse", "transmission", "shadow"])) == pytest.approx(2.0, rel=1e-6)
    assert centre(mirror_image(["diffuse", "transmission", "shadow"])) == 0.0


@pytest.mark.parametrize("visibility,seen", [(None, True), (NOT_CAMERA, False), (["camera"], True)])
def test_a_sphere_light_shows_only_to_the_rays_that_see_it(visibility, seen):
    scene = ppm_core.Scene()
    scene.add_material("floor", base_color=(0.5, 0.5, 0.5))
    square(scene, "floor", 4.0, 0.0, 0)
    scene.add_light("sphere", position=(0.0, 0.0, 1.0), radius=0.3, power=100.0, visibility=visibility)
    camera = np.eye(4)
    camera[2, 3] = 3.0
    scene.set_camera(camera, 16, 16, projection="orthographic", ortho_scale=2.0)
    inside = render(scene)[7:9, 7:9].mean()  # pixels within 0.18 of the axis, all inside the ball's disc
    light_radiance = 100.0 / (4 * np.pi * np.pi * 0.3 ** 2)
    if seen:
        assert inside == pytest.approx(light_radiance, rel=1e-6)
    else:
        assert 0.0 < inside < 0.2 * light_radiance  # the floor under it


def test_intersect_passes_through_what_the_ray_kind_does_not_see():
    scene = floor_scene(occluder=NOT_CAMERA)
    origins, directions = np.array([[0.0, 0.0, 3.0]] * 2), np.array([[0.0, 0.0, -1.0]] * 2)
    assert scene.intersect(origins, directions, ray_kind="camera")["t"] == pytest.approx([3.0, 3.0])
    assert scene.intersect(origins, directions, ray_kind="shadow")["t"] == pytest.approx([2.0, 2.0])
    assert scene.intersect(origins, directions)["t"] == pytest.approx([2.0, 2.0])


@pytest.mark.parametrize("call,message", [
    (lambda s: s.add_sphere("s", (0, 0, 0), 1.0, 0, visibility="camera"), "list of ray kinds"),
    (lambda s: s.add_sphere("s", (0, 0, 0), 1.0, 0, visibility=["camera", "volume"]), "'volume'"),
    (lambda s: s.add_light("point", visibility=[1]), "as strings"),
    (lambda s: s.intersect(np.zeros((1, 3)), np.ones((1, 3)), ray_kind="eye"), "ray_kind must be one of"),
])
def test_bad_visibility_is_named(call, message):
    scene = ppm_core.Scene()
    scene.add_material("m")
    with pytest.raises(ValueError, match=message):
        call(scene)
