"""Textures kept compact (sRGB or linear bytes, half floats) and decoded on lookup: the image is the
one the same colours give as floats, the memory is what the storage promises, and unusable texels
are an error or, when asked, black and counted."""

import numpy as np
import pytest

import ppm_core


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def textured_plane(pixels=None, base_color=(1.0, 1.0, 1.0), **texture_args):
    """A plane under a point light seen by an orthographic camera, its colour from `pixels`."""
    scene = ppm_core.Scene()
    texture = scene.add_texture("t", pixels, **texture_args) if pixels is not None else -1
    scene.add_material("m", base_color=base_color, texture=texture)
    corners = np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], dtype=float)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    scene.add_mesh("plane", corners, np.array([[0, 1, 2], [0, 2, 3]]), uvs=uvs)
    scene.add_light("point", position=(0.0, 0.0, 1.0), power=100.0)
    camera = np.eye(4)
    camera[2, 3] = 2.0
    scene.set_camera(camera, 16, 12, projection="orthographic", ortho_scale=4.0)
    return scene


def render(scene):
    renderer = ppm_core.Renderer(scene, photons_per_pass=3000, samples_per_pixel=2, threads=1, seed=5)
    renderer.run(passes=3)
    return renderer.image()[..., :3]


def uniform(value, dtype, channels=4, size=8):
    pixels = np.ones((size, size, channels), dtype=dtype)
    pixels[..., :3] = value
    return pixels


def test_srgb_bytes_decode_to_the_linear_colour():
    byte = np.array([40, 128, 230], dtype=np.uint8)
    textured = render(textured_plane(uniform(byte, np.uint8)))
    plain = render(textured_plane(base_color=tuple(srgb_to_linear(byte / 255.0))))
    assert textured.mean() > 0.0
    np.testing.assert_allclose(textured.mean(axis=(0, 1)), plain.mean(axis=(0, 1)), rtol=1e-3)


def test_linear_bytes_decode_to_byte_over_255():
    byte = np.array([40, 128, 230], dtype=np.uint8)
    textured = render(textured_plane(uniform(byte, np.uint8), storage="linear8"))
    plain = render(textured_plane(base_color=tuple(byte / 255.0)))
    np.testing.assert_allclose(textured.mean(axis=(0, 1)), plain.mean(axis=(0, 1)), rtol=1e-3)


def test_floats_quantized_to_bytes_are_the_bytes():
    """Blender hands a byte image over as byte / 255 floats: stored as srgb8 they are the same bytes."""
    rng = np.random.default_rng(3)
    byte = rng.integers(0, 256, size=(8, 8, 4), dtype=np.uint8)
    from_bytes = render(textured_plane(byte))
    from_floats = render(textured_plane(byte.astype(np.float32) / 255.0, storage="srgb8"))
    np.testing.assert_array_equal(from_bytes, from_floats)


def test_half_floats_keep_the_colour():
    color = (0.5, 0.25, 0.125)  # exact in half precision
    textured = render(textured_plane(uniform(color, np.float32)))
    plain = render(textured_plane(base_color=color))
    np.testing.assert_array_equal(textured, plain)


def test_rgb_is_rgba_with_opaque_alpha():
    rng = np.random.default_rng(4)
    rgba = rng.integers(0, 256, size=(8, 8, 4), dtype=np.uint8)
    rgba[..., 3] = 255
    np.testing.assert_array_equal(render(textured_plane(rgba)), render(textured_plane(rgba[..., :3].copy())))


@pytest.mark.parametrize("dtype,storage,bytes_per_texel", [
    (np.uint8, None, 4), (np.float32, None, 8), (np.float64, "half", 8), (np.float32, "srgb8", 4),
])
def test_memory_is_the_storage(dtype, storage, bytes_per_texel):
    scene = ppm_core.Scene()
    index = scene.add_texture("t", np.zeros((30, 20, 4), dtype=dtype), storage=storage)
    info = scene.texture_info(index)
    assert (info["width"], info["height"]) == (20, 30)
    assert info["bytes"] == 20 * 30 * bytes_per_texel
    assert info["storage"] == storage or (storage is None and info["storage"] == ("srgb8" if dtype == np.uint8
                                                                                    else "half"))


def test_max_rgb_is_the_brightest_decoded_channel():
    scene = ppm_core.Scene()
    pixels = np.zeros((2, 2, 4), dtype=np.uint8)
    pixels[1, 0] = (0, 200, 0, 255)
    pixels[0, 1, 3] = 255  # alpha does not count
    assert scene.texture_info(scene.add_texture("t", pixels))["max_rgb"] == pytest.approx(
        float(srgb_to_linear(200 / 255.0)), rel=1e-6)
    signed_zero = np.full((2, 2, 4), -0.0, dtype=np.float32)
    signed_zero[0, 0, 1] = 0.25
    assert scene.texture_info(scene.add_texture("z", signed_zero))["max_rgb"] == 0.25
    huge = scene.add_texture("h", np.full((2, 2, 4), 1e30, dtype=np.float32))
    assert scene.texture_info(huge)["max_rgb"] == 65504.0  # the largest half


@pytest.mark.parametrize("bad,channel,message", [
    (np.nan, 1, r"pixel \(x 1, y 0\) has a NaN or Inf component"),
    (-np.inf, 2, r"pixel \(x 1, y 0\) has a NaN or Inf component"),
    (np.nan, 3, r"pixel \(x 1, y 0\) has a NaN or Inf component"),  # alpha: unused, but must be finite
    (-0.5, 0, r"pixel \(x 1, y 0\) has a negative colour component -0.5"),
])
def test_unusable_texels_are_an_error_or_black_on_request(bad, channel, message):
    pixels = uniform((0.5, 0.5, 0.5), np.float32, size=4)
    pixels[0, 1, channel] = bad
    pixels[3, 3, channel] = bad
    with pytest.raises(ValueError, match=message):
        ppm_core.Scene().add_texture("t", pixels)
    scene = ppm_core.Scene()
    info = scene.texture_info(scene.add_texture("t", pixels, clear_unusable=True))
    cleared = pixels.copy()
    if np.isfinite(bad):  # a negative colour channel is stored as 0
        assert (info["negative_texels"], info["not_finite_texels"], info["most_negative"]) == (2, 0, bad)
        cleared[0, 1, channel] = cleared[3, 3, channel] = 0.0
    else:  # the texel is stored black
        assert (info["negative_texels"], info["not_finite_texels"]) == (0, 2)
        cleared[0, 1] = cleared[3, 3] = (0.0, 0.0, 0.0, 1.0)
    np.testing.assert_array_equal(render(textured_plane(pixels, clear_unusable=True)),
                                  render(textured_plane(cleared)))


@pytest.mark.parametrize("call,message", [
    (lambda s: s.add_texture("t", np.zeros((2, 2, 4), np.uint8), storage="half"), "stored as bytes"),
    (lambda s: s.add_texture("t", np.zeros((2, 2, 4)), storage="png"), "storage"),
    (lambda s: s.add_texture("t", np.zeros((2, 2, 4)), storage=3), "storage must be"),
    (lambda s: s.add_texture("t", np.zeros((0, 2, 4))), "width and height must be positive"),
    (lambda s: s.add_texture("t", np.zeros((2, 2, 4), np.complex64)), "real numbers"),
])
def test_bad_arguments_are_named(call, message):
    with pytest.raises(ValueError, match=message):
        call(ppm_core.Scene())


def test_srgb_bytes_are_interpolated_as_encoded_then_decoded():
    # As Cycles: between a black and a white texel, the middle is decode(0.5) = 0.214, not 0.5.
    # Two texels across U; the camera's middle column looks at u = 0.5, halfway between their centres.
    black_white = np.zeros((1, 2, 4), np.uint8)
    black_white[0, 1, :3] = 255
    black_white[..., 3] = 255
    srgb = render(textured_plane(black_white))
    linear = render(textured_plane(black_white, storage="linear8"))
    middle = slice(7, 9)  # of 16 columns over x in [-2, 2], the plane's u = (x + 3) / 6
    ratio = srgb[:, middle].mean() / linear[:, middle].mean()
    assert ratio == pytest.approx(float(srgb_to_linear(0.5)) / 0.5, rel=0.05)
