"""An image around the scene as its light (Blender's Environment Texture): the mapping of directions
to texels, its light on surfaces by direct light and photons, and its sampling density."""

import math

import numpy as np
import pytest

import ppm_core


def direction_of_texel(x, y, width, height):
    """The world direction Cycles' equirectangular mapping sends to the centre of texel (x, y)."""
    u, v = (x + 0.5) / width, (y + 0.5) / height
    azimuth, elevation = 2 * math.pi * (0.5 - u), math.pi * (v - 0.5)
    return np.array([math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                     math.sin(elevation)])


def sun_image(direction, radius_degrees, radiance, width=720, height=360):
    """A black equirectangular image with a disc of `radiance` around `direction`, and the disc's
    solid angle (the sum of its texels')."""
    image = np.zeros((height, width, 4), np.float32)
    image[..., 3] = 1.0
    ys, xs = np.mgrid[0:height, 0:width]
    u, v = (xs + 0.5) / width, (ys + 0.5) / height
    azimuth, elevation = 2 * np.pi * (0.5 - u), np.pi * (v - 0.5)
    dirs = np.stack([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth), np.sin(elevation)], -1)
    inside = dirs @ direction > math.cos(math.radians(radius_degrees))
    image[inside, :3] = radiance
    texel_solid_angle = np.cos(elevation) * (2 * np.pi / width) * (np.pi / height)
    return image, float(texel_solid_angle[inside].sum())


def box_scene():
    """A floor and a wall (so that there is indirect light), seen from above at an angle."""
    scene = ppm_core.Scene()
    grey = scene.add_material("grey", base_color=(0.6, 0.6, 0.6))
    quad = np.array([[0, 1, 2], [0, 2, 3]])
    scene.add_mesh("floor", np.array([[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], float), quad, materials=grey)
    scene.add_mesh("wall", np.array([[-2, 2, 0], [2, 2, 0], [2, 2, 2], [-2, 2, 2]], float), quad, materials=grey)
    camera = np.array([[1, 0, 0, 0], [0, 0.8, -0.6, -3.0], [0, 0.6, 0.8, 3.0], [0, 0, 0, 1]], float)
    scene.set_camera(camera, 48, 36, fov=1.0)
    return scene


def render(scene, passes=16, photons=20000):
    renderer = ppm_core.Renderer(scene, photons_per_pass=photons, samples_per_pixel=4, threads=2, seed=4)
    renderer.run(passes=passes)
    return renderer.image()[..., :3]


def test_a_uniform_image_lights_like_the_constant_background():
    constant = box_scene()
    constant.set_background((0.7, 0.7, 0.7))
    image = box_scene()
    image.set_environment(image.add_texture("sky", np.full((16, 32, 4), 0.35, np.float32)), strength=(2, 2, 2))
    a, b = render(constant), render(image)
    assert a.mean() > 0.1
    assert b.mean() == pytest.approx(a.mean(), rel=0.01)
    np.testing.assert_allclose(b.mean(axis=(0, 1)), a.mean(axis=(0, 1)), rtol=0.01)


def test_a_worlds_textures_are_replaced_without_piling_up_and_a_materials_are_kept():
    """remove_textures_from drops the world's textures (the world goes black until set again; a
    rendered scene renders again as a fresh one would) and refuses to drop a material's."""
    scene = box_scene()
    scene.add_material("printed", texture=scene.add_texture("label", np.full((4, 4, 4), 0.5, np.float32)))
    count = scene.texture_count
    for strength in (1.0, 3.0, 2.0):
        scene.remove_textures_from(count)
        sky = scene.add_texture("sky", np.full((16, 32, 4), 0.35, np.float32))
        scene.set_environment(sky, strength=(strength,) * 3)
        first = render(scene, passes=4)
    assert scene.texture_count == count + 1
    fresh = box_scene()
    fresh.add_material("printed", texture=fresh.add_texture("label", np.full((4, 4, 4), 0.5, np.float32)))
    fresh.set_environment(fresh.add_texture("sky", np.full((16, 32, 4), 0.35, np.float32)), strength=(2.0,) * 3)
    np.testing.assert_array_equal(first, render(fresh, passes=4))
    scene.remove_textures_from(count)
    assert render(scene, passes=4).max() == 0.0  # no world: no light
    with pytest.raises(ValueError, match="printed"):
        scene.remove_textures_from(0)
    assert scene.texture_count == count


def test_a_small_disc_in_the_image_lights_like_a_sun():
    """Direct light (the environment's density finds the disc) and photons (emitted by it) together:
    the image of a 3-degree disc of radiance L equals that of a sun of irradiance L * solid angle."""
    direction = np.array([math.cos(math.radians(50)) * 0.6, math.cos(math.radians(50)) * 0.8,
                          math.sin(math.radians(50))])
    pixels, solid_angle = sun_image(direction, 3.0, 5000.0)
    by_image = box_scene()
    by_image.set_environment(by_image.add_texture("sun", pixels))
    by_sun = box_scene()
    by_sun.add_light("sun", power=5000.0 * solid_angle, direction=tuple(-direction), angle=math.radians(6.0))
    a, b = render(by_sun), render(by_image)
    assert a.mean() > 0.1
    assert b.mean() == pytest.approx(a.mean(), rel=0.02)
    # In the wall's shadow, photons only; away from its edge, which the disc's texels (bilinear,
    # a quarter of a degree wider) blur a little more than the sun.
    shadowed = a.mean(axis=2) < 0.3 * a.mean()
    shadowed[1:-1, 1:-1] &= shadowed[:-2, 1:-1] & shadowed[2:, 1:-1] & shadowed[1:-1, :-2] & shadowed[1:-1, 2:]
    assert shadowed.sum() > 10
    assert b.mean(axis=2)[shadowed].mean() == pytest.approx(a.mean(axis=2)[shadowed].mean(), rel=0.05)


def seen_along(world, pixels, rotation):
    """What a camera ray escaping along `world` sees of the image `pixels` under `rotation`."""
    scene = ppm_core.Scene()
    scene.add_material("m")
    scene.set_environment(scene.add_texture("t", pixels), world_to_texture=rotation)
    forward = -world  # the camera looks down its local -Z
    up = np.array([0.0, 0.0, 1.0]) if abs(world[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(up, forward)
    right /= np.linalg.norm(right)
    camera = np.eye(4)
    camera[:3, 0], camera[:3, 1], camera[:3, 2] = right, np.cross(forward, right), forward
    scene.set_camera(camera, 1, 1, fov=1e-4)
    renderer = ppm_core.Renderer(scene, photons_per_pass=1, samples_per_pixel=1, threads=1)
    renderer.run(passes=1)
    return renderer.image()[0, 0, :3]


@pytest.mark.parametrize("rotation", [np.eye(4), np.array([[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])])
def test_escaping_rays_see_the_texel_cycles_maps_their_direction_to(rotation):
    """A 4x2 image of distinct colours, looked at along the direction of each texel's centre."""
    colours = np.arange(1, 9, dtype=np.float32).reshape(2, 4)
    pixels = np.ones((2, 4, 4), np.float32)
    pixels[..., :3] = colours[..., None] * np.array([1.0, 0.5, 0.25], np.float32)
    for y in range(2):
        for x in range(4):
            world = rotation[:3, :3].T @ direction_of_texel(x, y, 4, 2)
            np.testing.assert_allclose(seen_along(world, pixels, rotation), pixels[y, x, :3], rtol=1e-3,
                                       err_msg=f"texel {x}, {y}")


@pytest.mark.parametrize("call,message", [
    (lambda s, t: s.set_environment(t + 1), "texture index out of range"),
    (lambda s, t: s.set_environment(t, world_to_texture=np.diag([2.0, 1.0, 1.0, 1.0])), "must be a rotation"),
    (lambda s, t: s.set_environment(t, world_to_texture=np.diag([-1.0, 1.0, 1.0, 1.0])), "not a reflection"),
    (lambda s, t: s.set_environment(t, strength=(1.0, -1.0, 1.0)), "strength"),
    (lambda s, t: s.set_environment(t, projection="cube"), "projection must be one of"),
])
def test_bad_environments_are_named(call, message):
    scene = ppm_core.Scene()
    texture = scene.add_texture("t", np.ones((2, 4, 4), np.float32))
    with pytest.raises(ValueError, match=message):
        call(scene, texture)
