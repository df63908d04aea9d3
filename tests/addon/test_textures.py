"""Blender images reach the core compact (bytes as bytes, floats as halves) by either way in (the
file's bytes through imbuf in Blender 5.2+, Image.pixels elsewhere), and both give the same texture."""

import os

import bpy
import numpy as np
import pytest

from ppm_render import core
from ppm_render.export import Cancelled, build_scene
from ppm_render.export import image as image_export
from ppm_render.export.camera import Frame

ppm_core = core.load()
READS_FILE_BYTES = hasattr(image_export.imbuf, "types") and hasattr(image_export.imbuf.types.ImBuf, "with_buffer")


def saved_png(tmp_path, name="pattern", width=24, height=16, colorspace="sRGB"):
    """A byte PNG of a known pattern, saved and reloaded as Blender users' textures are."""
    image = bpy.data.images.new(name, width, height, alpha=True)
    rng = np.random.default_rng(7)
    image.pixels.foreach_set((rng.integers(0, 256, width * height * 4) / 255.0).astype(np.float32))
    image.filepath_raw = str(tmp_path / f"{name}.png")
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)
    loaded = bpy.data.images.load(str(tmp_path / f"{name}.png"))
    loaded.colorspace_settings.name = colorspace
    return loaded


def rendered(texture_in):
    """An image of a plane coloured by the texture that `texture_in(scene)` adds."""
    scene = ppm_core.Scene()
    index = texture_in(scene)
    scene.add_material("m", texture=index, base_color=(1, 1, 1))
    corners = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    uvs = (corners[:, :2] + 1) / 2
    scene.add_mesh("plane", corners, np.array([[0, 1, 2], [0, 2, 3]]), uvs=uvs)
    scene.add_light("point", position=(0.0, 0.0, 1.0), power=50.0)
    camera = np.eye(4)
    camera[2, 3] = 2.0
    scene.set_camera(camera, 24, 16, projection="orthographic", ortho_scale=2.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=2000, samples_per_pixel=1, threads=1, seed=3)
    renderer.run(passes=2)
    return renderer.image(), scene.texture_info(index)


@pytest.mark.parametrize("colorspace,storage", [("sRGB", "srgb8"), ("Non-Color", "linear8")])
def test_file_bytes_and_pixels_give_the_same_texture(tmp_path, colorspace, storage):
    image = saved_png(tmp_path, colorspace=colorspace)
    assert image_export.can_read_file_bytes(image) == READS_FILE_BYTES
    if READS_FILE_BYTES:
        assert image_export.add_file_bytes(ppm_core.Scene(), image, storage) is not None
    from_file, info = rendered(lambda scene: image_export.add_texture(scene, image)[0])
    assert not image.has_data  # Blender's own copy is not kept (or, reading the file, never loaded)
    from_pixels, pixels_info = rendered(lambda scene: image_export.add_pixels(scene, image, storage))
    assert info == pixels_info and info["storage"] == storage and info["bytes"] == 24 * 16 * 4
    assert from_file[..., :3].mean() > 0.0
    np.testing.assert_array_equal(from_file, from_pixels)


def test_a_packed_image_is_read_like_its_file(tmp_path):
    image = saved_png(tmp_path)
    unpacked, _ = rendered(lambda scene: image_export.add_texture(scene, image)[0])
    image.pack()
    (tmp_path / "pattern.png").unlink()
    if READS_FILE_BYTES:
        assert image_export.add_file_bytes(ppm_core.Scene(), image, "srgb8") is not None
    packed, info = rendered(lambda scene: image_export.add_texture(scene, image)[0])
    assert info["storage"] == "srgb8"
    np.testing.assert_array_equal(packed, unpacked)


def test_an_image_painted_on_is_read_from_its_pixels(tmp_path):
    image = saved_png(tmp_path)
    image.pixels[0] = 0.0  # makes the image dirty: its file no longer holds what Blender shows
    assert image.is_dirty and not image_export.can_read_file_bytes(image)
    from_image, _ = rendered(lambda scene: image_export.add_texture(scene, image)[0])
    from_pixels, _ = rendered(lambda scene: image_export.add_pixels(scene, image, "srgb8"))
    np.testing.assert_array_equal(from_image, from_pixels)


def test_float_images_are_half_floats():
    image = bpy.data.images.new("hdr", 8, 4, float_buffer=True)
    image.pixels.foreach_set(np.full(8 * 4 * 4, 0.375, dtype=np.float32))
    core_scene = ppm_core.Scene()
    index, repaired = image_export.add_texture(core_scene, image)
    info = core_scene.texture_info(index)
    assert repaired is None and info["storage"] == "half" and info["bytes"] == 8 * 4 * 8
    assert info["max_rgb"] == 0.375


def test_a_missing_file_is_reported(tmp_path):
    image = saved_png(tmp_path, "wood")
    (tmp_path / "wood.png").unlink()
    with pytest.raises(ValueError, match="image 'wood.png' has no pixels"):
        image_export.add_texture(ppm_core.Scene(), image)


def test_esc_during_the_export_stops_it():
    bpy.ops.mesh.primitive_plane_add()
    bpy.ops.object.camera_add(location=(0, 0, 5))
    bpy.context.scene.camera = bpy.context.object
    asked = []
    depsgraph = bpy.context.evaluated_depsgraph_get()
    frame = Frame.from_render_settings(bpy.context.scene.render)
    with pytest.raises(Cancelled):
        build_scene(ppm_core, depsgraph, frame, print, lambda: asked.append(1) or True)
    assert asked == [1]


def test_packed_udim_tiles_are_read_from_the_blend_file_with_their_files_gone(tmp_path):
    import tempfile
    for number in (1001, 1002, 1011):
        saved_png(tmp_path, f"packed.{number}", width=4, height=4)
    image = bpy.data.images["packed.1001.png"]
    image.source = "TILED"
    image.pack()
    for number in (1001, 1002, 1011):
        (tmp_path / f"packed.{number}.png").unlink()
    images_before, temporary_before = len(bpy.data.images), set(os.listdir(tempfile.gettempdir()))
    scene = ppm_core.Scene()
    pairs, repaired = image_export.add_tiles(scene, image)
    assert [number for number, _ in pairs] == [1001, 1002, 1011] and repaired is None
    assert [scene.texture_info(index)["width"] for _, index in pairs] == [4, 4, 4]
    assert len(bpy.data.images) == images_before  # no data-block and no unpacked copy left behind
    assert not {name for name in os.listdir(tempfile.gettempdir()) if name.startswith("ppm_tile_")} - temporary_before


def test_udim_tiles_are_read_file_by_file_and_never_as_data_blocks_off_the_main_thread(tmp_path):
    import threading
    for number in (1001, 1002, 1011):
        saved_png(tmp_path, f"tiles.{number}", width=4, height=4)
    image = bpy.data.images["tiles.1001.png"]
    image.source = "TILED"  # Blender finds the other tiles by the file name
    images_before = len(bpy.data.images)
    pairs, repaired = image_export.add_tiles(ppm_core.Scene(), image)
    assert [number for number, _ in pairs] == [1001, 1002, 1011] and repaired is None
    assert len(bpy.data.images) == images_before  # each tile's data-block removed again
    # An interactive render runs the export on its own thread: no data-blocks there (imbuf reads bytes
    # from Blender 5.2 on; before, the tiles are left to background renders, with the reason).
    outcome = []

    def export():
        try:
            outcome.append(image_export.add_tiles(ppm_core.Scene(), image)[0])
        except ValueError as error:
            outcome.append(str(error))

    thread = threading.Thread(target=export)
    thread.start()
    thread.join()
    if READS_FILE_BYTES:
        assert [number for number, _ in outcome[0]] == [1001, 1002, 1011]
    else:
        assert "background render" in outcome[0]
    assert len(bpy.data.images) == images_before
