"""Denoising: Blender's own Open Image Denoise called by denoise.py, and the Denoising Albedo,
Denoising Normal and Noisy Image passes and the denoised Combined the engine writes when asked."""

import os
import sys

import numpy as np
import pytest

from conftest import ROOT, bpy, camera_looking_down, read_exr, render_file, shader_material
from ppm_render import core, denoise, engine, passes

sys.path.insert(0, os.path.join(ROOT, "blend_scenes"))
import core_scenes  # noqa: E402

ppm_core = core.load()
COLOUR = (0.2, 0.5, 0.7)


def floor_scene():
    """A floor of one diffuse colour filling the view of a camera looking straight down."""
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(-20, -20, 0), (20, -20, 0), (20, 20, 0), (-20, 20, 0)], [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", mesh)
    scene.collection.objects.link(floor)
    floor.data.materials.append(shader_material("paint", "ShaderNodeBsdfDiffuse", Color=(*COLOUR, 1.0)))
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    lamp.location = (0.3, 0.2, 2.0)
    scene.collection.objects.link(lamp)
    camera_looking_down(scene, 4.0, 40, 30)
    return scene


@pytest.fixture
def written(monkeypatch):
    """The passes the engine writes: name -> (pixels, whether the result has that pass)."""
    out = {}
    original = passes.write_pass

    def spy(result, name, pixels):
        out[name] = (np.array(pixels), result.layers[0].passes.get(name) is not None)
        original(result, name, pixels)

    monkeypatch.setattr(passes, "write_pass", spy)
    return out


def test_blenders_open_image_denoise_is_found():
    assert denoise.available() == (True, "")  # official Blender builds and bpy ship it


def test_denoising_data_gives_the_surface_colour_and_cycles_camera_space_normal(written, tmp_path):
    render_file(floor_scene(), tmp_path / "d.exr", passes=1, photons_per_pass=2000, denoising_data=True)
    assert {"Denoising Albedo", "Denoising Normal"} <= set(written) and "Noisy Image" not in written
    albedo, registered = written["Denoising Albedo"]
    assert registered and albedo.shape == (30, 40, 3)
    np.testing.assert_allclose(albedo, np.broadcast_to(COLOUR, albedo.shape), atol=1e-4)
    normal, registered = written["Denoising Normal"]
    # The floor faces the camera: (0, 0, -1) in Cycles' camera space, which looks along +z.
    assert registered
    np.testing.assert_allclose(normal, np.broadcast_to((0, 0, -1), normal.shape), atol=1e-4)


def test_denoise_writes_the_denoised_combined_and_keeps_the_noisy_image(written, monkeypatch, tmp_path):
    calls = []
    real = denoise.denoise
    monkeypatch.setattr(denoise, "denoise", lambda *args: calls.append(args) or real(*args))
    image = render_file(floor_scene(), tmp_path / "n.exr", passes=2, photons_per_pass=500, denoise=True,
                        denoising_data=True)
    assert len(calls) == 1
    noisy = written["Noisy Image"][0][::-1]  # bottom-up, as written
    assert written["Noisy Image"][1] and noisy.shape == (30, 40, 4)
    assert np.abs(image[..., :3] - noisy[..., :3]).max() > 1e-3  # Combined is the denoised image
    np.testing.assert_array_equal(image[..., 3], noisy[..., 3])  # alpha as it was
    assert image[..., :3].std() < noisy[..., :3].std()  # the floor's noise smoothed


def test_without_a_denoiser_the_noisy_image_is_kept_with_a_warning(monkeypatch, tmp_path):
    warnings = []
    monkeypatch.setattr(denoise, "available", lambda: (False, "no library here"))
    monkeypatch.setattr(engine.PPMRenderEngine, "warn", lambda self, message: warnings.append(message))
    image = render_file(floor_scene(), tmp_path / "w.exr", passes=1, photons_per_pass=500, denoise=True)
    assert any("Denoise skipped: no library here" in w for w in warnings)
    assert image[..., :3].mean() > 0.0


def test_denoising_a_noisy_box_brings_it_closer_to_the_reference():
    """Four stochastic passes of the diffuse Cornell box against its long reference (bench/references):
    the denoised image's error, as the eye sees it (tone-mapped x / (1 + x)), is about half the noisy
    one's (measured 0.46-0.48 over seeds 1-5; bench/README.md, "Denoising", has the figures at equal
    time and where it smears)."""
    reference = read_exr(os.path.join(ROOT, "bench", "references", "core_cornell_diffuse.exr"))[..., :3]
    height, width = reference.shape[:2]
    renderer = ppm_core.Renderer(core_scenes.cornell_diffuse(width, height), photons_per_pass=50_000,
                                 hit_points="stochastic", seed=3, threads=2)
    renderer.run(passes=4)
    noisy = renderer.image()
    features = renderer.denoising_features()
    denoised = denoise.denoise(noisy, features["albedo"], features["normal"])

    def tone_mapped_rmse(image):
        return float(np.sqrt(((image[..., :3] / (1 + image[..., :3]) - reference / (1 + reference)) ** 2).mean()))

    assert tone_mapped_rmse(denoised) < 0.6 * tone_mapped_rmse(noisy)


def test_denoise_refuses_guides_of_another_size():
    with pytest.raises(ValueError, match="albedo"):
        denoise.denoise(np.zeros((4, 5, 3)), np.zeros((5, 4, 3)))
