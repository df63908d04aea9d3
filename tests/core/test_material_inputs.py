"""A mixture's inputs (image textures looked up at the hit's UV) driving lobe parameters: a
colour, a roughness (of a layer too) or a weight's factor. A uniform texture renders exactly as the
constant it holds; a texture that differs across the surface gives each part what its value gives;
bad references are refused with a message."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core

SIZE = 24


def texture(scene, bottom, top=None):
    """A float texture of value `bottom` in its lower rows (v < 0.5, the sphere's lower half) and
    `top` above (alpha 0.25 everywhere)."""
    texels = np.zeros((8, 8, 4), np.float32)
    texels[:4, :, :3] = bottom
    texels[4:, :, :3] = bottom if top is None else top
    texels[..., 3] = 0.25
    return scene.add_texture("values", texels, storage="half")


def lit_ball(lobes, inputs=None, textures=()):
    """A ball of `lobes` lit by a point light beside the camera, against black: its highlight shows
    the roughness. `textures`: (bottom, top) values, added before the material."""
    scene = ppm_core.Scene()
    for values in textures:
        texture(scene, *values)
    ball = scene.add_material("ball", "mixture", lobes=lobes, inputs=inputs)
    scene.add_sphere("ball", (0.0, 0.0, 0.0), 1.0, ball)
    scene.add_light("point", name="lamp", power=500.0, position=(1.5, -4.0, 1.5))
    scene.set_camera(core_scenes.look_at((0.0, -3.0, 0.0), (0.0, 0.0, 0.0)), SIZE, SIZE, fov=math.radians(45))
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=5, hit_points="stochastic")
    renderer.run(passes=6)
    image = renderer.image()[..., :3]  # (a smooth ball stores no hit points: finite_rgb would refuse it)
    assert np.isfinite(image).all() and (image >= 0.0).all()
    return image


def coat_over(base_roughness, coat_roughness, **coat):
    return [{"kind": "dielectric", "parts": "reflection", "layer": True, "ior": 1.5, "roughness": coat_roughness,
             **coat},
            {"kind": "glossy", "weight": 0.5, "color": (0.9, 0.6, 0.3), "roughness": base_roughness},
            {"kind": "diffuse", "weight": 0.5, "color": (0.2, 0.4, 0.8)}]


@pytest.mark.parametrize("textured, constant, inputs", [
    ([{"kind": "glossy", "color": 0.8, "roughness": 1.0, "roughness_input": 0}],
     [{"kind": "glossy", "color": 0.8, "roughness": 0.5}], [(0, "grey")]),
    (coat_over(0.5, 1.0, roughness_input=0), coat_over(0.5, 0.5), [(0, "grey")]),
    ([{"kind": "diffuse", "color": (1.0, 0.5, 1.0), "color_input": (0, "sqrt")}],
     [{"kind": "diffuse", "color": (0.5, 0.25, 0.5)}], [(0, "rgb")]),
    ([{"kind": "diffuse", "color": 0.8, "weight_inputs": [(0, "complement")]},
      {"kind": "glossy", "color": 0.8, "roughness": 0.5, "weight_inputs": [(0, "fraction")]}],
     [{"kind": "diffuse", "color": 0.8, "weight": 0.75}, {"kind": "glossy", "color": 0.8, "roughness": 0.5,
                                                          "weight": 0.25}], [(0, "alpha")]),
], ids=["roughness", "layer roughness", "sqrt colour", "mix factor from alpha"])
def test_a_uniform_input_renders_as_the_constant_it_holds(textured, constant, inputs):
    # The texture holds 0.5 (0.25 where its square root is taken) and alpha 0.25: half floats hold
    # them exactly, so both renders do the same arithmetic.
    value = 0.25 if inputs[0][1] == "rgb" else 0.5
    image = lit_ball(textured, inputs, textures=[(value, None)])
    expected = lit_ball(constant)
    assert expected.max() > 0.05
    np.testing.assert_allclose(image, expected, rtol=1e-5, atol=1e-7)


def test_each_part_of_the_surface_gets_its_own_value():
    # Roughness 0.1 on the upper half and 0.6 below (eye paths follow both, sampling the lamp): each half as
    # the ball of that constant roughness renders it, away from the seam at the equator.
    def glossy(roughness, **extra):
        return [{"kind": "glossy", "color": 0.8, "roughness": roughness, **extra}]

    image = lit_ball(glossy(1.0, roughness_input=0), [(0, "grey")], textures=[(0.6, 0.1)])
    smooth, rough = lit_ball(glossy(0.1)), lit_ball(glossy(0.6))
    upper, lower = slice(0, SIZE // 2 - 3), slice(SIZE // 2 + 3, SIZE)
    assert not np.allclose(smooth[upper], rough[upper], rtol=0.05)  # the halves can tell them apart
    # Half floats hold 0.1 as 0.0999756 and 0.6 as 0.600098: near, not equal.
    np.testing.assert_allclose(image[upper], smooth[upper], rtol=0.02, atol=2e-3)
    np.testing.assert_allclose(image[lower], rough[lower], rtol=0.02, atol=2e-3)


@pytest.mark.parametrize("lobes, inputs, message", [
    ([{"kind": "diffuse", "color_input": 1}], [(0, "rgb")], "input 1"),
    ([{"kind": "diffuse", "color_input": 0}], [(7, "rgb")], "texture that does not exist"),
    ([{"kind": "diffuse", "color_input": (0, "cube")}], [(0, "rgb")], "transform"),
    ([{"kind": "diffuse"}], [(0, "red")], "channel"),
    ([{"kind": "diffuse"}], [(0, "rgb")] * 9, "at most 8 inputs"),
    ([{"kind": "diffuse", "weight_inputs": [0, 0, 0]}], [(0, "rgb")], "at most 2 weight_inputs"),
])
def test_bad_input_references_are_refused_with_a_message(lobes, inputs, message):
    scene = ppm_core.Scene()
    texture(scene, 0.5)
    with pytest.raises(ValueError, match=message):
        scene.add_material("ball", "mixture", lobes=lobes, inputs=inputs)


def test_inputs_belong_to_mixtures_only():
    scene = ppm_core.Scene()
    texture(scene, 0.5)
    with pytest.raises(ValueError, match="mixture"):
        scene.add_material("ball", "diffuse", inputs=[(0, "rgb")])


def mapped_plane(normal_rgb, light_direction, normal_map=None, sign=1.0):
    """A diffuse plane (z = 0, tangent +x, bitangent sign `sign`) under a sun, seen from above; its
    normal map a uniform texture of `normal_rgb` (None: no map). Returns the mean radiance."""
    scene = ppm_core.Scene()
    texels = np.zeros((2, 2, 4), np.float32)
    texels[..., :3] = normal_rgb if normal_rgb is not None else 0.5
    texels[..., 3] = 1.0
    texture = scene.add_texture("normals", texels, storage="half")
    material = scene.add_material("plane", "mixture", lobes=[{"kind": "diffuse", "color": 0.5}],
                                  inputs=[(texture, "rgb")] if normal_rgb is not None else None,
                                  normal_map=normal_map if normal_rgb is not None else None)
    corners = np.array([[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], dtype=float)
    triangles = np.array([[0, 1, 2], [0, 2, 3]])
    tangents = np.tile([1.0, 0.0, 0.0, sign], (4, 1))
    scene.add_mesh("plane", corners, triangles, uvs=corners[:, :2] / 4.0 + 0.5, tangents=tangents, materials=material)
    scene.add_light("sun", power=3.0, direction=light_direction)
    camera = np.eye(4)
    camera[2, 3] = 2.0
    scene.set_camera(camera, 8, 8, projection="orthographic", ortho_scale=2.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=2000, threads=2, seed=3)
    renderer.run(passes=2)
    return float(renderer.image()[..., :3].mean())


def encoded(normal):
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    return tuple((n + 1.0) / 2.0)


@pytest.mark.parametrize("space", ["tangent", "world"])
def test_a_normal_map_turns_the_shading_normal(space):
    # Sun from straight above: a normal tilted by 40 degrees towards +x receives cos(40) of it.
    down = (0.0, 0.0, -1.0)
    tilted = (math.sin(math.radians(40)), 0.0, math.cos(math.radians(40)))
    flat = mapped_plane(None, down)
    assert flat > 0.01
    as_is = mapped_plane(encoded((0, 0, 1)), down, {"input": 0, "space": space})
    turned = mapped_plane(encoded(tilted), down, {"input": 0, "space": space})
    halfway = mapped_plane(encoded(tilted), down, {"input": 0, "space": space, "strength": 0.0})
    assert as_is == pytest.approx(flat, rel=1e-3)
    assert turned == pytest.approx(flat * math.cos(math.radians(40)), rel=0.01)
    assert halfway == pytest.approx(flat, rel=1e-3)  # strength 0: the normal as it was


def test_the_bitangent_sign_mirrors_the_maps_y():
    # A normal tilted towards the map's +y faces +y in the world with sign +1 and -y with sign -1: a
    # sun from +y (45 degrees up) lights the first more.
    tilted = encoded((0.0, math.sin(math.radians(30)), math.cos(math.radians(30))))
    from_plus_y = (0.0, -1.0, -1.0)
    plus = mapped_plane(tilted, from_plus_y, {"input": 0}, sign=1.0)
    minus = mapped_plane(tilted, from_plus_y, {"input": 0}, sign=-1.0)
    assert plus / minus == pytest.approx(math.cos(math.radians(15)) / math.cos(math.radians(75)), rel=0.02)


@pytest.mark.parametrize("normal_map, message", [
    ({"input": 1}, "input 1"), ({"strength": 1.0}, "needs an input"), ({"input": 0, "space": "object"}, "space"),
    ({"input": 0, "strength": float("nan")}, "strength"), ({"input": 0, "bump": 1}, "unknown normal_map key"),
])
def test_bad_normal_maps_are_refused_with_a_message(normal_map, message):
    scene = ppm_core.Scene()
    texture(scene, 0.5)
    with pytest.raises(ValueError, match=message):
        scene.add_material("ball", "mixture", lobes=[{"kind": "diffuse"}], inputs=[(0, "rgb")], normal_map=normal_map)


def half_white():
    texels = np.zeros((1, 4, 4), np.float32)
    texels[0, :2] = 1.0
    texels[..., 3] = 1.0
    return texels


def lamp_over_floor(emission, texels=None, direct_light="sampled"):
    """An emissive quad (facing down, 1 m above a diffuse floor) seen with the floor from beside:
    its emission times `texels` (a row of them running along x), if given."""
    scene = ppm_core.Scene()
    inputs, emission_input = None, -1
    if texels is not None:
        inputs, emission_input = [(scene.add_texture("texels", texels, storage="half"), "rgb")], 0
    lamp = scene.add_material("lamp", "emission", base_color=(0.0, 0.0, 0.0), emission=(emission,) * 3,
                              inputs=inputs, emission_input=emission_input)
    floor = scene.add_material("floor", base_color=(0.5, 0.5, 0.5))
    quad = np.array([[-0.5, -0.5, 1.0], [0.5, -0.5, 1.0], [0.5, 0.5, 1.0], [-0.5, 0.5, 1.0]])
    # U runs with x across the lamp: texels 1, 1, 0, 0 (bilinear blending only across the middle and
    # the repeating edges).
    uvs = np.array([[0.0, 0.5], [1.0, 0.5], [1.0, 0.5], [0.0, 0.5]])
    scene.add_mesh("lamp", quad, np.array([[0, 2, 1], [0, 3, 2]]), uvs=uvs, materials=lamp)
    ground = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], dtype=float)
    scene.add_mesh("floor", ground, np.array([[0, 1, 2], [0, 2, 3]]), materials=floor)
    camera = np.eye(4)
    camera[2, 3] = 3.0
    scene.set_camera(camera, 32, 32, projection="orthographic", ortho_scale=4.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=50_000, threads=2, seed=9, direct_light=direct_light)
    renderer.run(passes=8)
    return renderer.image()[..., :3].mean(axis=2)


@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_a_textured_emission_emits_and_shows_what_its_texture_says(direct_light):
    # Seen from above the lamp hides the floor under it: look at the floor around it. Twice the
    # emission on half the lamp gives the floor the same light in all, more on the lit half's side.
    textured = lamp_over_floor(2.0, half_white(), direct_light)
    uniform = lamp_over_floor(1.0, None, direct_light)
    around = np.ones((32, 32), bool)
    around[8:24, 8:24] = False  # the lamp's footprint and a margin
    assert textured[around].mean() == pytest.approx(uniform[around].mean(), rel=0.03)
    left, right = textured[:, :6].mean(), textured[:, 26:].mean()  # columns run along +x
    assert left > 1.5 * right
    # The lamp itself (columns and rows 12 to 19): 2 inside its white half, 0 inside its black one.
    assert textured[12:20, 13:15].mean() == pytest.approx(2.0, rel=0.01)
    assert textured[12:20, 17:19].max() < 0.01


@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_a_textured_emission_lights_with_detail_its_mean_estimate_misses(direct_light):
    # One white texel of 64: the 16 lookups that estimate each triangle's power all miss it, yet the
    # lamp gives the floor the light of its true mean (a uniform lamp of 1/64 the emission).
    texels = np.zeros((1, 64, 4), np.float32)
    texels[0, 37, :3] = 1.0
    texels[..., 3] = 1.0
    textured = lamp_over_floor(64.0, texels, direct_light)
    uniform = lamp_over_floor(1.0, None, direct_light)
    around = np.ones((32, 32), bool)
    around[8:24, 8:24] = False
    assert textured[around].mean() == pytest.approx(uniform[around].mean(), rel=0.05)
